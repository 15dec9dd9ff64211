//! Where the time goes on the long-interface strip (run by hand, prints timings):
//!
//! ```text
//! cargo test -p signorini-scene-tests --release --test pdas_measure -- --ignored --nocapture
//! ```
//!
//! The strip of the issue (20 × 0.02 on a 20 × 0.04 foundation, hmax 0.01, floating in y or
//! clamped at its left end) is meshed and assembled here from an inline scene; each quantity is
//! the median of five runs in one process, after one warm-up, so that the ratios do not mix
//! cold and warm caches.  Printed: the floor, the AMD orderings of A and K, the analysis and
//! numeric LDLᵀ of K, faer's LLᵀ of A and our LDLᵀ of A alone (same pattern: the cost of LDLᵀ
//! over LLᵀ), nnz(L) of A and of K (the fill the contact coupling adds), one solve, and the
//! whole pdas solve.
#![allow(clippy::unwrap_used)]

mod common;

use std::time::{Duration, Instant};

use signorini_core::solve::floor_time;
use signorini_qp::linalg::fill_reducing_order;
use signorini_qp::{QpBackend, QpProblem, QpStatus, SolveOptions};

use signorini_pdas::internals::{KktFactor, KktMatrix};
use signorini_pdas::PdasBackend;

fn median(mut f: impl FnMut() -> Duration) -> f64 {
    f();
    let mut t: Vec<f64> = (0..5).map(|_| f().as_secs_f64() * 1e3).collect();
    t.sort_by(f64::total_cmp);
    t[2]
}

fn timed(f: impl FnOnce()) -> Duration {
    let clock = Instant::now();
    f();
    clock.elapsed()
}

#[test]
#[ignore = "measurement, run by hand"]
fn where_the_time_goes_on_the_strip() {
    for clamped in [false, true] {
        let p = common::strip_scaled(20.0, clamped, (0.0, 20.0));
        let floor = median(|| floor_time(&p).unwrap());
        let amd_a = median(|| timed(|| drop(fill_reducing_order(&p.stiffness).unwrap())));
        let kkt = KktMatrix::new(&p).unwrap();
        let amd_k = median(|| timed(|| drop(fill_reducing_order(kkt.matrix()).unwrap())));
        let analyse = median(|| timed(|| drop(KktFactor::analyse(kkt.matrix(), p.dofs()))));
        let mut factor = KktFactor::analyse(kkt.matrix(), p.dofs()).unwrap();
        factor.allocate().unwrap();
        let numeric = median(|| timed(|| factor.factor(kkt.matrix(), 1e-13, 1e-10).unwrap()));
        let pattern = signorini_qp::linalg::CholeskyPattern::analyse(&p.stiffness);
        let llt_a = match &pattern {
            Ok(pattern) => median(|| timed(|| drop(pattern.factor(&p.stiffness)))),
            Err(_) => f64::NAN,
        };
        let a_only = QpProblem {
            constraints: sprs::CsMat::zero((0, p.dofs())).to_csc(),
            gap: Vec::new(),
            blocks: Vec::new(),
            ..p.clone()
        };
        let kkt_a = KktMatrix::new(&a_only).unwrap();
        let mut factor_a = KktFactor::analyse(kkt_a.matrix(), p.dofs()).unwrap();
        factor_a.allocate().unwrap();
        let ldlt_a = median(|| timed(|| factor_a.factor(kkt_a.matrix(), 1e-13, 1e-10).unwrap()));
        println!(
            "nnz(L) of A {:.3e}, of K {:.3e}; LDLᵀ(A) {ldlt_a:.1} ms",
            factor_a.nnz_l() as f64,
            KktFactor::analyse(kkt.matrix(), p.dofs()).unwrap().nnz_l() as f64
        );
        let mut rhs = vec![1.0; kkt.dim()];
        let solve = median(|| timed(|| factor.solve_in_place(&mut rhs)));
        let mut status = QpStatus::NumericalError;
        let mut message = String::new();
        let pdas = median(|| {
            let clock = Instant::now();
            let s = PdasBackend::default()
                .solve(&p, &SolveOptions::default())
                .unwrap();
            let t = clock.elapsed();
            status = s.status;
            message = s.message.unwrap_or_default();
            t
        });
        println!(
            "strip {} ({} DOFs, {} rows): floor {floor:.1} ms; AMD(A) {amd_a:.1}, AMD(K) {amd_k:.1}, \
             analyse(K) {analyse:.1}, LDLᵀ(K) {numeric:.1}, LLᵀ(A) {llt_a:.1}, solve {solve:.2} ms; pdas {pdas:.1} ms = \
             {:.2}× floor, {status}: {message}",
            if clamped { "clamped" } else { "floating" },
            p.dofs(),
            p.rows(),
            pdas / floor
        );
    }
}
