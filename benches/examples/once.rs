//! Times one run of every step and backend at each benched size (no criterion): the check that
//! decides which `solve/*` benches are registered.  `cargo run --release -p signorini-benches
//! --example once [hmax...]`.

use std::time::Instant;

use signorini_benches::{solve_options, Bench, Case, HMAX};
use signorini_core::linalg::CholeskyPattern;
use signorini_core::solve::solve_model;

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("hmax is a number"))
        .collect();
    let sizes = if args.is_empty() { HMAX.to_vec() } else { args };
    for hmax in sizes {
        let t = Instant::now();
        let case = Case::new(hmax);
        println!(
            "hmax {hmax}: {} (free {}, rows {}), prepared in {:.2?}",
            case.id(),
            case.qp.dofs(),
            case.qp.rows(),
            t.elapsed()
        );
        let t = Instant::now();
        let pattern = CholeskyPattern::analyse(&case.qp.stiffness).expect("analyse");
        let chol = pattern.factor(&case.qp.stiffness).expect("factor");
        let mut x = case.qp.load.clone();
        chol.solve_in_place(&mut x);
        let floor = t.elapsed();
        println!("  floor (analyse+factor+solve) {floor:.2?}");
        for bench in Bench::ALL {
            let mut backend = bench.backend();
            let t = Instant::now();
            let sol = solve_model(&case.model, &case.qp, backend.as_mut(), &solve_options())
                .expect("solve runs");
            let dt = t.elapsed();
            println!(
                "  {:<11} {:>10.2?}  {:>7.1}x floor  status {:?}  iterations {}",
                bench.name(),
                dt,
                dt.as_secs_f64() / floor.as_secs_f64(),
                sol.status,
                sol.iterations
            );
        }
    }
}
