//! Builders and the solve helper shared by the integration tests.
#![allow(dead_code, unused_imports, clippy::unwrap_used)]

use signorini_pdas::{PdasBackend, PdasSettings};
use signorini_qp::{QpProblem, QpSolution, QpStatus};

pub use signorini_qp::examples::{csc_from_triplets as csc, rel_diff};

/// A QP from triplets.
pub fn qp(
    n: usize,
    a: &[(usize, usize, f64)],
    f: Vec<f64>,
    m: usize,
    b: &[(usize, usize, f64)],
    g: Vec<f64>,
) -> QpProblem {
    signorini_qp::examples::qp_from_triplets(n, a, f, m, b, g).unwrap()
}

/// Solves with `settings` at `tol` and returns the solution with the core's checked status.
pub fn solve_with(settings: PdasSettings, problem: &QpProblem, tol: f64) -> (QpSolution, QpStatus) {
    solve_in(settings, problem, tol, Units::Own)
}

pub use signorini_qp::examples::Units;

/// [`solve_with`] in the chosen units; the answer must be finite with multipliers ≥ 0 whatever
/// its status.
pub fn solve_in(
    settings: PdasSettings,
    problem: &QpProblem,
    tol: f64,
    units: Units,
) -> (QpSolution, QpStatus) {
    let mut backend = PdasBackend::new(settings);
    let (sol, status) =
        signorini_qp::examples::solve_checked(&mut backend, problem, tol, units).unwrap();
    assert!(
        sol.x.iter().chain(&sol.multipliers).all(|v| v.is_finite()),
        "non-finite answer: {:?}",
        sol.message
    );
    assert!(sol.multipliers.iter().all(|l| *l >= 0.0));
    (sol, status)
}

/// Solves with the default settings.
pub fn solve(problem: &QpProblem, tol: f64) -> (QpSolution, QpStatus) {
    solve_with(PdasSettings::default(), problem, tol)
}
