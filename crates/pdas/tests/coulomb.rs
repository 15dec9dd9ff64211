//! pdas's semismooth Newton for Coulomb friction (`QpBackend::solve_coulomb`) against answers
//! known by hand, judged by the residuals with each Coulomb row bounded by μ max(0, λₙ) of the
//! answer itself.
#![allow(clippy::unwrap_used)]

mod common;

use common::qp;
use signorini_pdas::PdasBackend;
use signorini_qp::{
    checked_status, ConstraintBlock, CoulombLink, CoulombRows, QpBackend, QpProblem, QpStatus,
    ResidualScales, SolveOptions,
};

const TOL: f64 = 1e-9;

/// The masses' initial gap G to the ground.
const GAP: f64 = 0.05;

/// `blocks` point masses on springs k (DOFs 2i: x, 2i + 1: y), each a gap G above the ground,
/// pressed onto it by N and pulled sideways by tᵢ: normal rows −yᵢ ≤ G, tangential rows xᵢ
/// (gap 0), Coulomb μ.
/// The provisional bounds of the box block are deliberately wrong (1e3): only μ λₙ counts.
fn blocks(k: f64, pressure: f64, pulls: &[f64], mu: f64) -> (QpProblem, CoulombRows) {
    let count = pulls.len();
    let n = 2 * count;
    let a: Vec<(usize, usize, f64)> = (0..n).map(|j| (j, j, k)).collect();
    let mut f = vec![0.0; n];
    let mut b = Vec::new();
    for (i, t) in pulls.iter().enumerate() {
        f[2 * i] = *t;
        f[2 * i + 1] = -pressure;
        b.push((i, 2 * i + 1, -1.0));
        b.push((count + i, 2 * i, 1.0));
    }
    let mut gap = vec![GAP; count];
    gap.extend(vec![0.0; count]);
    let problem = qp(n, &a, f, 2 * count, &b, gap)
        .with_blocks(vec![
            ConstraintBlock::NonNegative { rows: count },
            ConstraintBlock::Box {
                bounds: vec![1e3; count],
            },
        ])
        .unwrap();
    let links = (0..count)
        .map(|i| CoulombLink {
            row: count + i,
            normal_row: i,
            mu,
        })
        .collect();
    let rows = CoulombRows::new(&problem, links).unwrap();
    (problem, rows)
}

#[test]
fn pulled_beyond_mu_n_a_block_slips_by_the_excess_and_below_it_sticks() {
    // k = 2, N = 1, G = 0.05: the spring takes k G = 0.1, so λₙ = 0.9 and μ λₙ = 0.27 at
    // μ = 0.3.  Pull 0.5 slips, x = (0.5 − 0.27)/2 = 0.115, λₜ = +0.27; pull −0.9 slips the
    // other way, x = −0.315, λₜ = −0.27; pull 0.2 < 0.27 sticks, x = 0, λₜ = 0.2.  Exact in
    // exact arithmetic; 1e-12 leaves room for the refinement's round-off.
    let (k, pressure, mu) = (2.0, 1.0, 0.3);
    let pulls = [0.5, -0.9, 0.2];
    let (problem, rows) = blocks(k, pressure, &pulls, mu);
    let options = SolveOptions::default();
    let sol = PdasBackend::default()
        .solve_coulomb(&problem, &rows, &options)
        .unwrap();
    let scales = ResidualScales::of(&problem);
    let residuals = rows.residuals(&problem, &scales, &sol.x, &sol.multipliers);
    assert_eq!(
        checked_status(sol.status, &residuals, TOL),
        QpStatus::Solved,
        "{:?} {residuals:?}",
        sol.message
    );
    let want_x = [0.115, -0.315, 0.0];
    let want_t = [0.27, -0.27, 0.2];
    for i in 0..pulls.len() {
        assert!((sol.x[2 * i] - want_x[i]).abs() < 1e-12, "{:?}", sol.x);
        assert!((sol.x[2 * i + 1] + GAP).abs() < 1e-12, "{:?}", sol.x);
        assert!((sol.multipliers[i] - (pressure - k * GAP)).abs() < 1e-12);
        assert!((sol.multipliers[3 + i] - want_t[i]).abs() < 1e-12);
    }
}

#[test]
fn a_backend_without_its_own_coulomb_method_refuses_by_name() {
    // The trait's default: a backend that has no method for the coupled conditions says so
    // (the core then runs the fixed point) rather than solving Tresca with the given bounds.
    struct TrescaOnly;
    impl QpBackend for TrescaOnly {
        fn name(&self) -> &'static str {
            "tresca-only"
        }
        fn supports(&self, _: signorini_qp::BlockKind) -> bool {
            true
        }
        fn solve_valid(
            &mut self,
            _: &QpProblem,
            _: &SolveOptions,
        ) -> Result<signorini_qp::QpSolution, signorini_qp::QpError> {
            unreachable!("solve_coulomb must not fall back to the Tresca solve")
        }
    }
    let (problem, rows) = blocks(2.0, 1.0, &[0.5], 0.3);
    assert!(
        !TrescaOnly.solves_coulomb(&problem) && PdasBackend::default().solves_coulomb(&problem)
    );
    let e = TrescaOnly
        .solve_coulomb(&problem, &rows, &SolveOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("tresca-only") && e.contains("Coulomb"), "{e}");
}

#[test]
fn started_from_its_own_answer_pdas_settles_in_one_step() {
    // A load path hands each increment the previous answer (SolveOptions::warm_start): pdas
    // predicts its first set from it.  Started from the exact answer, that set is the final one,
    // so one step settles it (from every row active the Coulomb blocks take 2, the Laplacian
    // chain with 20 rows several) — and the answer is the same.
    use signorini_qp::{examples::laplacian_with_bounds, QpSolution, WarmStart};
    use std::sync::Arc;
    // The default options with `answer` as the warm start.
    let from = |answer: &QpSolution| SolveOptions {
        warm_start: Some(Arc::new(WarmStart {
            x: answer.x.clone(),
            multipliers: answer.multipliers.clone(),
        })),
        ..SolveOptions::default()
    };
    let (problem, rows) = blocks(2.0, 1.0, &[0.5, -0.9, 0.2], 0.3);
    let cold = PdasBackend::default()
        .solve_coulomb(&problem, &rows, &SolveOptions::default())
        .unwrap();
    let warm = PdasBackend::default()
        .solve_coulomb_valid(&problem, &rows, &from(&cold))
        .unwrap();
    assert!(cold.iterations > 1, "{:?}", cold.message);
    assert_eq!(warm.iterations, 1, "{:?}", warm.message);
    assert_eq!(warm.status, QpStatus::Solved);
    for (a, b) in cold.x.iter().zip(&warm.x) {
        assert!((a - b).abs() < 1e-12);
    }
    let chain = laplacian_with_bounds(200, 20);
    let cold = PdasBackend::default()
        .solve_in_given_units(&chain, &SolveOptions::default())
        .unwrap();
    let warm = PdasBackend::default()
        .solve_in_given_units(&chain, &from(&cold))
        .unwrap();
    assert!(cold.iterations > 1, "{:?}", cold.message);
    assert_eq!(warm.status, QpStatus::Solved, "{:?}", warm.message);
    assert_eq!(
        warm.iterations, 1,
        "{:?} (cold: {})",
        warm.message, cold.iterations
    );
}
