//! pdas on the QPs of `signorini_qp::examples` beyond the conformance suite
//! (tests/conformance.rs): one solve without rows, the infeasibility message, redundant rows,
//! and the limits (iterations, time, settings).
#![allow(clippy::unwrap_used)]

mod common;

use std::time::Duration;

use common::{qp, solve, solve_with};
use signorini_pdas::{PdasBackend, PdasSettings, StartSet};
use signorini_qp::examples::{infeasible, spring_chain, two_rows, unconstrained, Known};
use signorini_qp::{QpBackend, QpError, QpStatus, SolveOptions};

/// The tolerance the answer is judged by; the known optima are exact rationals, and the
/// KKT systems here are 1×1 to 11×11 with condition numbers below 10³, so an answer meeting
/// 1e-12 is within 1e-9 of them (the comparison tolerance of `Known::mismatch`).
const TOL: f64 = 1e-12;

fn check(known: &Known, settings: PdasSettings) {
    let (sol, status) = solve_with(settings.clone(), &known.problem, TOL);
    assert_eq!(
        status,
        QpStatus::Solved,
        "{:?} {:?}",
        settings.start,
        sol.message
    );
    if let Some(why) = known.mismatch(&sol.x, &sol.multipliers, 1e-9) {
        panic!("{:?}: {why}", settings.start);
    }
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

/// Without rows every start is one solve (the interior start has no set to predict).
#[test]
fn no_rows_is_one_solve() {
    let known = unconstrained();
    for settings in every_start() {
        check(&known, settings.clone());
        let (sol, _) = solve_with(settings.clone(), &known.problem, TOL);
        assert_eq!(sol.iterations, 1, "{:?}: {:?}", settings.start, sol.message);
    }
}

#[test]
fn contradicting_rows_are_primal_infeasible() {
    // x ≤ −1 and x ≥ 1: the certificate y = (1, 1) has Bᵀy = 0, gᵀy = −2 < 0.
    for s in every_start() {
        let (sol, status) = solve_with(s.clone(), &infeasible(), TOL);
        assert_eq!(
            status,
            QpStatus::PrimalInfeasible,
            "{:?}: {:?}",
            s.start,
            sol.message
        );
        assert!(sol.message.unwrap().contains("primal infeasible"));
    }
}

#[test]
fn compatible_redundant_rows_are_solved() {
    // x ≤ 1 twice (B rank-deficient on the active set, but consistent): x = 1, λ₁ + λ₂ = 2.
    let p = qp(
        1,
        &[(0, 0, 2.0)],
        vec![4.0],
        2,
        &[(0, 0, 1.0), (1, 0, 1.0)],
        vec![1.0, 1.0],
    );
    let (sol, status) = solve(&p, 1e-10);
    assert_eq!(status, QpStatus::Solved, "{:?}", sol.message);
    assert!((sol.x[0] - 1.0).abs() < 1e-10);
    assert!((sol.multipliers[0] + sol.multipliers[1] - 2.0).abs() < 1e-9);
}

#[test]
fn a_tiny_time_limit_stops_with_time_limit() {
    let options = SolveOptions {
        time_limit: Some(Duration::from_nanos(1)),
        ..SolveOptions::default()
    };
    let known = spring_chain();
    let sol = PdasBackend::default()
        .solve(&known.problem, &options)
        .unwrap();
    assert_eq!(sol.status, QpStatus::TimeLimit, "{:?}", sol.message);
    assert!(sol.x.iter().all(|v| v.is_finite()));
}

#[test]
fn the_iteration_cap_is_honoured() {
    // Started from the empty set, the wall row is violated by the free solution: one
    // iteration cannot finish.
    let options = SolveOptions {
        max_iter: Some(1),
        ..SolveOptions::default()
    };
    let settings = PdasSettings {
        start: StartSet::Empty,
        ..Default::default()
    };
    let sol = PdasBackend::new(settings)
        .solve(&spring_chain().problem, &options)
        .unwrap();
    assert_eq!(sol.status, QpStatus::MaxIterations, "{:?}", sol.message);
    assert_eq!(sol.iterations, 1);
}

#[test]
fn a_bad_setting_is_an_error_not_a_panic() {
    let settings = PdasSettings {
        penalty: -1.0,
        ..Default::default()
    };
    let err = PdasBackend::new(settings)
        .solve(&two_rows().problem, &SolveOptions::default())
        .unwrap_err();
    assert!(matches!(err, QpError::Backend { .. }), "{err}");
    assert!(err.to_string().contains("penalty"));
}

#[test]
fn the_message_names_the_ordering_and_the_factor_size() {
    let (sol, _) = solve(&two_rows().problem, TOL);
    let message = sol.message.unwrap();
    assert!(
        message.contains("ordering ") && message.contains("nnz(L)"),
        "{message}"
    );
}

#[test]
fn verbose_prints_and_solves_the_same() {
    let options = SolveOptions {
        verbose: true,
        tol: TOL,
        ..SolveOptions::default()
    };
    let known = spring_chain();
    let sol = PdasBackend::default()
        .solve(&known.problem, &options)
        .unwrap();
    assert_eq!(sol.status, QpStatus::Solved);
    assert!(known.mismatch(&sol.x, &sol.multipliers, 1e-9).is_none());
}

#[test]
fn updates_and_factorisations_reach_the_same_answer() {
    updates_and_factorisations_agree(common::Units::Given);
}

/// The same chain nondimensionalised (what `solve` hands a backend since issue 19): without
/// low-rank updates, six fresh factorisations end `inaccurate` at 1e-10 (the residual misses by
/// a small factor: the chain's condition number ~1.6e6 leaves little room at that tolerance).
#[test]
#[ignore = "pdas without low-rank updates ends inaccurate at 1e-10 on the nondimensionalised 2000-node chain; open in issue 21"]
fn updates_and_factorisations_reach_the_same_answer_in_their_own_units() {
    updates_and_factorisations_agree(common::Units::Own);
}

fn updates_and_factorisations_agree(units: common::Units) {
    // A 1-D chain with 40 obstacle rows, most of them active: several active-set steps.
    // Both runs end on the same set with refined solves, so they agree to about
    // cond · ε ≈ (2000²) · 1e-16 ≈ 4e-10 relative; 1e-8 leaves room.
    let p = signorini_qp::examples::laplacian_with_bounds(2000, 40);
    let (a, status_a) = common::solve_in(PdasSettings::default(), &p, 1e-10, units);
    let no_updates = PdasSettings {
        max_update_rank: 0,
        ..Default::default()
    };
    let (b, status_b) = common::solve_in(no_updates, &p, 1e-10, units);
    assert_eq!(status_a, QpStatus::Solved, "{:?}", a.message);
    assert_eq!(status_b, QpStatus::Solved, "{:?}", b.message);
    assert!(b.message.unwrap().contains(" 0 low-rank updates"));
    assert!(common::rel_diff(&a.x, &b.x) < 1e-8);
    assert!(common::rel_diff(&a.multipliers, &b.multipliers) < 1e-8);
}

/// Four points on a plane (FCLIB's hand-written 2-D test problem, frictionless): A = 2I over
/// (x_a, y_a), each point pressed by −f_y onto y_a ≥ −g_a and pulled sideways by f_x, its x_a
/// touched by no row.  Exact answer: x_a = f_x/2, y_a = max(−f_y/2, −g_a), λ_a = max(f_y − 2g_a, 0).
/// pdas found the right set and solved it to a KKT system residual of 1e-16, but a point
/// pressed onto its obstacle does not move (y_a = 0): the residuals judged its round-off
/// penetration (≈ 1e-17) against the pair's own motion (the same 1e-17), relative penetration
/// 1, and the answer was `inaccurate` (fixed by `signorini_qp::BODY_MOTION_FLOOR`).
#[test]
fn four_points_with_untouched_dofs() {
    let mut a = sprs::TriMat::new((8, 8));
    for j in 0..8 {
        a.add_triplet(j, j, 2.0);
    }
    let f = vec![1.0, -2.0, 0.3, -2.0, 1.0, -2.0, 0.4, -1.0];
    let mut b = sprs::TriMat::new((4, 8));
    for r in 0..4 {
        b.add_triplet(r, 2 * r + 1, -1.0);
    }
    let g = vec![0.0, 0.0, 0.0, 1.0];
    let p = signorini_qp::QpProblem::try_new(a.to_csc(), f.clone(), b.to_csc(), g).unwrap();
    for units in [common::Units::Given, common::Units::Own] {
        let (sol, status) = common::solve_in(PdasSettings::default(), &p, TOL, units);
        assert_eq!(
            status,
            QpStatus::Solved,
            "{units:?}: {:?} {:?}",
            sol.message,
            sol.x
        );
        let x = [0.5, 0.0, 0.15, 0.0, 0.5, 0.0, 0.2, -0.5];
        for (j, (got, want)) in sol.x.iter().zip(x).enumerate() {
            assert!(
                (got - want).abs() < 1e-9,
                "{units:?}: x[{j}] = {got}, want {want}"
            );
        }
    }
}
