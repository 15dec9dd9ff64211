//! Builders and the solve helper shared by the integration tests.
#![allow(dead_code, clippy::unwrap_used)]

use signorini_core::qp::{
    checked_status, kkt_residuals, CscMatrix, QpBackend, QpProblem, QpSolution, QpStatus,
    SolveOptions,
};
use signorini_pdas::{PdasBackend, PdasSettings};
use sprs::TriMat;

/// A CSC matrix from (row, col, value) triplets (duplicates are summed).
pub fn csc(rows: usize, cols: usize, entries: &[(usize, usize, f64)]) -> CscMatrix {
    let mut t = TriMat::new((rows, cols));
    for &(i, j, v) in entries {
        t.add_triplet(i, j, v);
    }
    t.to_csc()
}

/// A QP from triplets.
pub fn qp(
    n: usize,
    a: &[(usize, usize, f64)],
    f: Vec<f64>,
    m: usize,
    b: &[(usize, usize, f64)],
    g: Vec<f64>,
) -> QpProblem {
    QpProblem::try_new(csc(n, n, a), f, csc(m, n, b), g).unwrap()
}

/// Solves with `settings` at `tol` and returns the solution with the core's checked status.
pub fn solve_with(settings: PdasSettings, problem: &QpProblem, tol: f64) -> (QpSolution, QpStatus) {
    let options = SolveOptions {
        tol,
        ..SolveOptions::default()
    };
    let sol = PdasBackend::new(settings).solve(problem, &options).unwrap();
    assert!(
        sol.x.iter().chain(&sol.multipliers).all(|v| v.is_finite()),
        "non-finite answer: {:?}",
        sol.message
    );
    assert!(sol.multipliers.iter().all(|l| *l >= 0.0));
    let r = kkt_residuals(problem, &sol.x, &sol.multipliers);
    let status = checked_status(sol.status, &r, tol);
    (sol, status)
}

/// Solves with the default settings.
pub fn solve(problem: &QpProblem, tol: f64) -> (QpSolution, QpStatus) {
    solve_with(PdasSettings::default(), problem, tol)
}

/// max |a − b| / max |b|.
pub fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs())).max(1e-300);
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale
}
