//! Where the time goes on the long-interface strip (run by hand, prints timings):
//!
//! ```text
//! cargo test -p signorini-pdas --release --lib measure -- --ignored --nocapture
//! ```
//!
//! The strip of the issue (20 × 0.02 on a 20 × 0.04 foundation, hmax 0.01, floating in y or
//! clamped at its left end) is meshed and assembled here from an inline scene; each quantity is
//! the median of five runs in one process, after one warm-up, so that the ratios do not mix
//! cold and warm caches.  Printed: the floor, the AMD orderings of A and K, the analysis and
//! numeric LDLᵀ of K, faer's LLᵀ of A and our LDLᵀ of A alone (same pattern: the cost of LDLᵀ
//! over LLᵀ), nnz(L) of A and of K (the fill the contact coupling adds), one solve, and the
//! whole pdas solve.
#![cfg(test)]
#![allow(clippy::unwrap_used)]

use std::time::{Duration, Instant};

use signorini_core::mesh::MeshLimits;
use signorini_core::model::{assemble, mesh_scene};
use signorini_core::scene::Scene;
use signorini_core::solve::{floor_time, ScaledQp};
use signorini_qp::linalg::fill_reducing_order;
use signorini_qp::{QpBackend, QpProblem, QpStatus, SolveOptions};

use crate::factor::KktFactor;
use crate::kkt::KktMatrix;
use crate::PdasBackend;

fn strip(length: f64, clamped: bool) -> QpProblem {
    strip_loaded(length, clamped, (0.0, length))
}

/// The strip with its traction on [load.0, load.1] only.
fn strip_loaded(length: f64, clamped: bool, load: (f64, f64)) -> QpProblem {
    let (load_from, load_to) = load;
    let components = if clamped { "" } else { "components = [\"x\"]" };
    let toml = format!(
        r#"
title = "strip"
[[body]]
name = "strip"
polygon = [[0, 1], [{length}, 1], [{length}, 1.02], [0, 1.02]]
hmax = 0.01
young = 1.0
poisson = 0.3
[[body]]
name = "foundation"
polygon = [[0, 0.96], [{length}, 0.96], [{length}, 1], [0, 1]]
hmax = 0.01
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "foundation"
region = [0, {length}, 0.96, 0.96]
[[dirichlet]]
body = "strip"
region = [0, 0, 1, 1.02]
{components}
[[neumann]]
body = "strip"
region = [{load_from}, {load_to}, 1.02, 1.02]
traction = [0, -1e-3]
[[contact]]
bodies = ["strip", "foundation"]
region = [0, {length}, 0.99, 1.01]
"#
    );
    let scene = Scene::from_toml(&toml).unwrap();
    let meshes = mesh_scene(&scene, &MeshLimits::default()).unwrap();
    ScaledQp::new(assemble(&scene, meshes).unwrap().qp).problem
}

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
        let p = strip(20.0, clamped);
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
