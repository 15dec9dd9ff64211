//! A long thin strip loaded on part of its length only (the scene of the issue's
//! strip-partial: a 20 × 0.02 strip floating in y on a 20 × 0.04 foundation, hmax 0.01,
//! traction on [8, 12]; 51 575 DOFs, 2001 contact rows).  Plain primal–dual active-set steps
//! flip tens of rows a step here and never settle (the contact Schur complement of a thin
//! strip is no M-matrix: releasing a row at the edge of the contact zone moves the strip far
//! away); before the interior-point continuation the backend stopped at `max-iterations`
//! after 100 steps (KKT residuals ~1e-2).
//!
//! The reference is an independent solve by a different algorithm: signorini's dual-ssn
//! backend (semismooth Newton on the dense condensed dual, `signorini solve
//! strip-partial.toml --backend dual-ssn`: solved, KKT residuals 3.0e-11, 789 steps) finds
//! the contact zone to be exactly rows 799..=1201 (403 rows, the loaded part plus one row on
//! each side), every other row open.  The set is a discrete fact, so it is compared exactly;
//! the answer itself is checked by the core's KKT residuals at the default tolerance 1e-9
//! (first-order conditions are sufficient for this convex QP, so meeting them bounds the
//! distance to the optimum).
#![allow(clippy::unwrap_used)]

mod common;

use signorini_pdas::PdasBackend;
use signorini_qp::{kkt_residuals, QpProblem, QpSolution, QpStatus};

#[test]
fn strip_loaded_on_part_of_its_length_is_solved() {
    let p = common::strip_scaled(20.0, false, (8.0, 12.0));
    assert_eq!(p.rows(), 2001);
    let (sol, status) = solve(&p, 1e-9);
    assert_eq!(status, QpStatus::Solved, "{:?}", sol.message);
    assert_eq!(sol.status, QpStatus::Solved, "{:?}", sol.message);
    let r = kkt_residuals(&p, &sol.x, &sol.multipliers);
    assert!(r.meet(1e-9), "{r:?}");
    let active: Vec<usize> = (0..p.rows())
        .filter(|&i| sol.multipliers[i] > 0.0)
        .collect();
    assert_eq!(
        active,
        (799..=1201).collect::<Vec<_>>(),
        "{:?}",
        sol.message
    );
}

/// The same strip clamped at its left end (A positive definite, no kernel; plain steps flip
/// here too), checked by the core's KKT residuals only (no independent reference run).
#[test]
fn clamped_strip_loaded_on_part_of_its_length_is_solved() {
    let p = common::strip_scaled(20.0, true, (8.0, 12.0));
    let (sol, status) = solve(&p, 1e-9);
    assert_eq!(status, QpStatus::Solved, "{:?}", sol.message);
    let r = kkt_residuals(&p, &sol.x, &sol.multipliers);
    assert!(r.meet(1e-9), "{r:?}");
}

/// pdas with its default settings at `tol`; its multipliers are never negative.
fn solve(problem: &QpProblem, tol: f64) -> (QpSolution, QpStatus) {
    let (sol, status) = common::solve(&mut PdasBackend::default(), problem, tol);
    assert!(sol.multipliers.iter().all(|l| *l >= 0.0));
    (sol, status)
}
