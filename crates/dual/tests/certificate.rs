//! `primal-infeasible` only with a Farkas certificate checked against B and g
//! (`signorini_qp::FarkasRay`), never from the size of an iterate.
#![allow(clippy::unwrap_used)]

mod common;

use common::{backends, qp};
use signorini_qp::{FarkasRay, QpBackend, QpProblem, QpStatus, SolveOptions, FARKAS_MARGIN};

/// Solves with every dual backend and checks each says `primal-infeasible` with a certificate
/// whose reach is at least the margin.
fn assert_certified_infeasible(p: &QpProblem) {
    for mut b in backends() {
        let sol = b.solve(p, &SolveOptions::default()).unwrap();
        let message = sol.message.clone().unwrap_or_default();
        assert_eq!(
            sol.status,
            QpStatus::PrimalInfeasible,
            "{}: {message}",
            b.name()
        );
        assert!(message.contains("primal infeasible"), "{message}");
        assert!(
            FarkasRay::reported_reach(&message).unwrap_or(0.0) >= FARKAS_MARGIN,
            "{message}"
        );
        assert!(sol.x.iter().chain(&sol.multipliers).all(|v| v.is_finite()));
    }
}

#[test]
fn contradicting_bounds_are_certified_infeasible() {
    // x ≤ −1 and −x ≤ −1: the exact ray y = (1, 1) has Bᵀy = 0 and gᵀy = −2.
    assert_certified_infeasible(&signorini_qp::examples::infeasible());
}

/// Two bodies, each two nodes on unit springs (node a–b and c–d, a and c tied to the ground by
/// a spring of stiffness 2), loaded; the slave node a faces the midpoint of the master segment
/// c–d, and two contact rows on the same geometry ask for the gap to stay open by 0.1
/// (u_a − ½(u_c + u_d) ≤ −0.1) and for the bodies to overlap by 0.05 at once
/// (½(u_c + u_d) − u_a ≤ −0.05).  No displacement does both: y = (1, 1) is an exact ray.
fn overlap_and_separate() -> QpProblem {
    let springs = [
        (0, 0, 3.0),
        (0, 1, -1.0),
        (1, 0, -1.0),
        (1, 1, 1.0),
        (2, 2, 3.0),
        (2, 3, -1.0),
        (3, 2, -1.0),
        (3, 3, 1.0),
    ];
    let rows = [
        (0, 0, 1.0),
        (0, 2, -0.5),
        (0, 3, -0.5),
        (1, 0, -1.0),
        (1, 2, 0.5),
        (1, 3, 0.5),
    ];
    qp(
        4,
        &springs,
        vec![0.3, 0.0, -0.2, 0.1],
        2,
        &rows,
        vec![-0.1, -0.05],
    )
}

#[test]
fn contact_rows_that_demand_overlap_and_separation_are_certified_infeasible() {
    assert_certified_infeasible(&overlap_and_separate());
}

/// Feasible, but only far away: u₀ − u₁ ≤ −1 and −u₀ + (1 + η) u₁ ≤ −1 hold together only for
/// u₁ ≤ −2/η.  With A = I and f = 0 the answer is both rows active: u = (−2/η − 1, −2/η),
/// λ₂ = (4/η + 1)/η, λ₁ = λ₂ + 2/η + 1.  The multipliers grow along y ≈ (1, 1) with
/// gᵀy = −2 < 0 and Bᵀy = (0, η): not a certificate (the core's reach is (4 + η)/η = 4e4 for
/// η = 1e-4, below the margin 1e8), yet before the certificate the dual monitor called it
/// `primal-infeasible` (dual-uzawa did: the growth was judged against the small early iterate
/// ‖x‖₁ ≈ 5e-4, not against the data).
fn nearly_parallel(eta: f64) -> QpProblem {
    qp(
        2,
        &[(0, 0, 1.0), (1, 1, 1.0)],
        vec![0.0, 0.0],
        2,
        &[(0, 0, 1.0), (0, 1, -1.0), (1, 0, -1.0), (1, 1, 1.0 + eta)],
        vec![-1.0, -1.0],
    )
}

#[test]
fn feasible_rows_met_only_far_away_are_never_called_infeasible() {
    let eta = 1e-4;
    let p = nearly_parallel(eta);
    let exact = [-2.0 / eta - 1.0, -2.0 / eta];
    for mut b in backends() {
        let sol = b.solve(&p, &SolveOptions::default()).unwrap();
        let message = sol.message.clone().unwrap_or_default();
        assert_ne!(
            sol.status,
            QpStatus::PrimalInfeasible,
            "{}: {message}",
            b.name()
        );
        assert!(sol.x.iter().chain(&sol.multipliers).all(|v| v.is_finite()));
        if sol.status == QpStatus::Solved {
            // The tolerance 1e-9 on the KKT residuals bounds the error in u by about
            // cond · 1e-9 relative; the 2 × 2 dual here has cond ≈ 4/η² = 4e8, and the
            // answer is checked to 1e-6 of |u| (u is exact in binary at η = 1e-4 up to
            // the rounding of 2/η).
            let err = (sol.x[0] - exact[0]).abs().max((sol.x[1] - exact[1]).abs());
            assert!(err <= 1e-6 * exact[1].abs(), "{}: {:?}", b.name(), sol.x);
        } else {
            assert!(
                message.contains("no certificate of primal infeasibility"),
                "{}: {message}",
                b.name()
            );
        }
    }
}
