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

use signorini_clarabel::ClarabelBackend;
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

/// Issue 21: the partial-contact strip in few factorisations.  Before the early hand-over to
/// the interior-point iteration (after the first plain step, which changes 689 rows here)
/// and its start shifted by the problem's scales, pdas took 13 factorisations on the floating
/// strip (7 plain steps, 3 interior, 3 exact solves) and 21 on the clamped one; after them 5
/// and 9.  Now the crossover follows the first interior step and fixes the few rows that set
/// gets wrong by low-rank updates, its plain steps counted from its own start: three
/// factorisations each (the all-active step, one interior step, the crossover; measured 3
/// and 3 + 5 updates; 5 and 9 before, which fail the bound), the least this method can take on a set
/// that the all-active step does not find.
#[test]
fn strip_loaded_on_part_of_its_length_takes_few_factorisations() {
    for (clamped, bound) in [(false, 3), (true, 3)] {
        let p = common::strip_scaled(20.0, clamped, (8.0, 12.0));
        let (sol, status) = solve(&p, 1e-9);
        assert_eq!(status, QpStatus::Solved, "{:?}", sol.message);
        let n = factorisations(sol.message.as_deref().unwrap_or(""));
        assert!(
            n <= bound,
            "clamped {clamped}: {n} factorisations > {bound}: {:?}",
            sol.message
        );
    }
}

/// A smaller partial-contact strip (4 × 0.02, load on [1.6, 2.4], 401 rows) solved by pdas and
/// by clarabel (an interior-point method, independent; dual-ssn stops `inaccurate` here): the
/// same contact rows, the same objective to 1e-8 relative (clarabel's tolerance; the objective
/// is first-order insensitive to the error) and the same x and λ to 1e-6
/// relative (limited by the condition of the strip's KKT system, ~1e6: the bound
/// `dual_long_interface.rs` argues for the fully pressed strip).
#[test]
#[ignore = "no independent reference solves this strip yet: clarabel stops AlmostSolved at 1e-8 and 1e-10, dual-ssn inaccurate (stalled, KKT 1.2e4)"]
fn small_partial_strip_agrees_with_clarabel() {
    let p = common::strip_scaled(4.0, false, (1.6, 2.4));
    let tol = 1e-10;
    let (sol, status) = solve(&p, tol);
    assert_eq!(status, QpStatus::Solved, "{:?}", sol.message);
    let mut clarabel = ClarabelBackend::default();
    // clarabel meets 1e-8 here, not 1e-10 (AlmostSolved).
    let (reference, ref_status) = common::solve(&mut clarabel, &p, 1e-8);
    assert_eq!(ref_status, QpStatus::Solved, "{:?}", reference.message);
    let set = |l: &[f64]| -> Vec<usize> { (0..l.len()).filter(|&i| l[i] > 0.0).collect() };
    let active = set(&sol.multipliers);
    assert!(active.len() < p.rows() / 2, "{} rows active", active.len());
    assert_eq!(active, set(&reference.multipliers));
    let objective = |x: &[f64]| {
        let ax = signorini_qp::mat_vec(&p.stiffness, x);
        0.5 * signorini_qp::dot(x, &ax) - signorini_qp::dot(&p.load, x)
    };
    let (f, f_ref) = (objective(&sol.x), objective(&reference.x));
    assert!((f - f_ref).abs() <= 1e-8 * f_ref.abs(), "{f} vs {f_ref}");
    println!("objective {:.1e}", (f - f_ref).abs() / f_ref.abs());
    let dx = common::rel_diff(&reference.x, &sol.x);
    let dl = common::rel_diff(&reference.multipliers, &sol.multipliers);
    println!("x differs by {dx:e}, λ by {dl:e}");
    assert!(dx < 1e-6 && dl < 1e-6, "x differs by {dx:e}, λ by {dl:e}");
}

/// The count N in pdas's message "…: N factorisations, …".
fn factorisations(message: &str) -> usize {
    message
        .split(" factorisations")
        .next()
        .and_then(|head| head.rsplit(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or(usize::MAX)
}

/// pdas with its default settings at `tol`; its multipliers are never negative.
fn solve(problem: &QpProblem, tol: f64) -> (QpSolution, QpStatus) {
    let (sol, status) = common::solve(&mut PdasBackend::default(), problem, tol);
    assert!(sol.multipliers.iter().all(|l| *l >= 0.0));
    (sol, status)
}
