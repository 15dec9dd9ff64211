//! Floating bodies (singular A with a known kernel): held only by contact, pushed away from it
//! (dual infeasible), and a rigid mode no row sees.
#![allow(clippy::unwrap_used)]

mod common;

use common::{qp, rel_diff, solve, solve_with};
use signorini_pdas::{PdasSettings, StartSet};
use signorini_qp::{QpProblem, QpStatus};

/// Body 1: DOF 0 held by a ground spring k1.  Body 2: DOFs 1, 2, 3 joined by springs k2, free
/// (kernel r = (0, 1, 1, 1)).  Contact: x0 − x1 ≤ gap.  Load `push` on DOF 3 (negative =
/// toward body 1).
fn floating(push: f64) -> QpProblem {
    let (k1, k2, gap) = (10.0, 4.0, 0.1);
    let a = [
        (0, 0, k1),
        (1, 1, k2),
        (1, 2, -k2),
        (2, 1, -k2),
        (2, 2, 2.0 * k2),
        (2, 3, -k2),
        (3, 2, -k2),
        (3, 3, k2),
    ];
    qp(
        4,
        &a,
        vec![0.0, 0.0, 0.0, push],
        1,
        &[(0, 0, 1.0), (0, 1, -1.0)],
        vec![gap],
    )
    .with_kernel(vec![vec![0.0, 1.0, 1.0, 1.0]])
    .unwrap()
}

fn every_start() -> Vec<PdasSettings> {
    StartSet::EVERY
        .into_iter()
        .map(|start| PdasSettings {
            start,
            ..Default::default()
        })
        .collect()
}

#[test]
fn floating_body_held_only_by_contact() {
    // Analytic: the contact force is p; x0 = −p/k1, body 2 sits at the gap and stretches.
    let p = 3.0;
    let (k1, k2, gap) = (10.0, 4.0, 0.1);
    let x0 = -p / k1;
    let x1 = x0 - gap;
    let expected = [x0, x1, x1 - p / k2, x1 - 2.0 * p / k2];
    // Every start, including the empty set, where the first K is singular but for ρ and the
    // rigid motion is ~1/ρ: the next set must catch it.
    for s in every_start() {
        let (sol, status) = solve_with(s.clone(), &floating(-p), 1e-12);
        assert_eq!(status, QpStatus::Solved, "{:?}: {:?}", s.start, sol.message);
        // Condition number of this 5×5 KKT system is below 10², so 1e-12 residuals give
        // answers within 1e-10.
        assert!(
            rel_diff(&sol.x, &expected) < 1e-10,
            "{:?}: {:?}",
            s.start,
            sol.x
        );
        assert!((sol.multipliers[0] - p).abs() < 1e-10 * p);
    }
}

#[test]
fn floating_body_pushed_away_is_dual_infeasible_not_nan() {
    for s in every_start() {
        let (sol, status) = solve_with(s.clone(), &floating(3.0), 1e-10);
        assert_eq!(
            status,
            QpStatus::DualInfeasible,
            "{:?}: {:?}",
            s.start,
            sol.message
        );
        assert!(sol.message.unwrap().contains("dual infeasible"));
    }
}

#[test]
fn a_rigid_mode_no_row_sees_is_dual_infeasible_at_once() {
    // Two bodies of one DOF each, both free (kernel e0, e1); the only row touches DOF 0, and
    // DOF 1 is loaded: nothing can hold it.
    let p = qp(
        2,
        &[(0, 0, 0.0), (1, 1, 0.0)],
        vec![-1.0, 1.0],
        1,
        &[(0, 0, -1.0)],
        vec![0.0],
    )
    .with_kernel(vec![vec![1.0, 0.0], vec![0.0, 1.0]])
    .unwrap();
    let (sol, status) = solve(&p, 1e-10);
    assert_eq!(status, QpStatus::DualInfeasible, "{:?}", sol.message);
    assert_eq!(sol.iterations, 0);
}

#[test]
fn a_wrong_kernel_vector_is_a_numerical_error() {
    let mut p = floating(-3.0);
    p.kernel = vec![vec![1.0, 0.0, 0.0, 0.0]];
    let (sol, status) = solve(&p, 1e-10);
    assert_eq!(status, QpStatus::NumericalError, "{:?}", sol.message);
    assert!(sol.message.unwrap().contains("not in the null space"));
}
