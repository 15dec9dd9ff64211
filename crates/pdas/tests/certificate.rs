//! pdas says `primal-infeasible` only with the core's Farkas certificate
//! (`signorini_qp::FarkasRay`), whose reach its message reports; feasible rows that meet
//! only far away are not certified.
#![allow(clippy::unwrap_used)]

mod common;

use common::{qp, solve};
use signorini_qp::{FarkasRay, QpProblem, QpStatus, FARKAS_MARGIN};

/// The tolerance the answers are judged by (the default).
const TOL: f64 = 1e-9;

/// A slave node a (DOF 0) and a master node c (DOF 1), each on a spring to the ground and
/// loaded, with two contact rows written at different scales: 2(u_a − u_c) ≤ −0.2 (keep a gap
/// of 0.1) and u_c − u_a ≤ −0.05 (overlap by 0.05).  The exact ray is y = (1, 2): Bᵀy = 0,
/// gᵀy = −0.3.
fn gap_and_overlap_at_different_scales() -> QpProblem {
    qp(
        2,
        &[(0, 0, 2.0), (1, 1, 5.0)],
        vec![1.0, -0.5],
        2,
        &[(0, 0, 2.0), (0, 1, -2.0), (1, 0, -1.0), (1, 1, 1.0)],
        vec![-0.2, -0.05],
    )
}

#[test]
fn contact_rows_that_demand_a_gap_and_an_overlap_are_certified_infeasible() {
    for p in [
        gap_and_overlap_at_different_scales(),
        signorini_qp::examples::infeasible(),
    ] {
        let (sol, status) = solve(&p, TOL);
        let message = sol.message.unwrap_or_default();
        assert_eq!(status, QpStatus::PrimalInfeasible, "{message}");
        assert!(
            FarkasRay::reported_reach(&message).unwrap_or(0.0) >= FARKAS_MARGIN,
            "{message}"
        );
    }
}

#[test]
fn feasible_rows_met_only_far_away_are_not_certified() {
    // u₀ − u₁ ≤ −1 and −u₀ + (1 + η)u₁ ≤ −1 hold together only for u₁ ≤ −2/η (see the dual
    // backend's test of the same name): the ray (1, 1) reaches only (4 + η)/η = 4e4 < 1e8.
    let eta = 1e-4;
    let p = qp(
        2,
        &[(0, 0, 1.0), (1, 1, 1.0)],
        vec![0.0, 0.0],
        2,
        &[(0, 0, 1.0), (0, 1, -1.0), (1, 0, -1.0), (1, 1, 1.0 + eta)],
        vec![-1.0, -1.0],
    );
    let (sol, status) = solve(&p, TOL);
    let message = sol.message.unwrap_or_default();
    assert_ne!(status, QpStatus::PrimalInfeasible, "{message}");
    if status != QpStatus::Solved {
        assert!(
            message.contains("no certificate of primal infeasibility"),
            "{message}"
        );
    }
}
