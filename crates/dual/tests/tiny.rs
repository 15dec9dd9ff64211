//! Tiny QPs with a hand-known optimum, an infeasible one, and limits.
#![allow(clippy::unwrap_used)]

mod common;

use common::{backends, qp, solve};
use signorini_dual::{DualBackend, DualSettings};
use signorini_qp::{QpBackend, QpStatus, SolveOptions};

#[test]
fn one_dof_active_constraint() {
    // min x² − 4x  s.t. x ≤ 1  →  x = 1, λ = 2.
    let p = qp(1, &[(0, 0, 2.0)], vec![4.0], 1, &[(0, 0, 1.0)], vec![1.0]);
    for mut b in backends() {
        let (sol, status) = solve(&mut b, &p, 1e-12);
        assert_eq!(status, QpStatus::Solved, "{}", b.name());
        assert!((sol.x[0] - 1.0).abs() < 1e-12, "{} {:?}", b.name(), sol.x);
        assert!((sol.multipliers[0] - 2.0).abs() < 1e-12, "{}", b.name());
    }
}

#[test]
fn one_dof_inactive_constraint() {
    // min x² − 4x  s.t. x ≤ 3  →  x = 2, λ = 0.
    let p = qp(1, &[(0, 0, 2.0)], vec![4.0], 1, &[(0, 0, 1.0)], vec![3.0]);
    for mut b in backends() {
        let (sol, status) = solve(&mut b, &p, 1e-12);
        assert_eq!(status, QpStatus::Solved, "{}", b.name());
        assert!((sol.x[0] - 2.0).abs() < 1e-12, "{}", b.name());
        assert_eq!(sol.multipliers[0], 0.0, "{}", b.name());
    }
}

#[test]
fn two_dofs_one_of_two_constraints_active() {
    // min ½‖x‖² − (2, 1)·x  s.t. x0 + x1 ≤ 1, x0 − x1 ≤ 5
    // → the first is active: x = (1, 0), λ = (1, 0).
    let p = qp(
        2,
        &[(0, 0, 1.0), (1, 1, 1.0)],
        vec![2.0, 1.0],
        2,
        &[(0, 0, 1.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, -1.0)],
        vec![1.0, 5.0],
    );
    for mut b in backends() {
        let (sol, status) = solve(&mut b, &p, 1e-12);
        assert_eq!(status, QpStatus::Solved, "{}", b.name());
        assert!(
            (sol.x[0] - 1.0).abs() < 1e-11 && sol.x[1].abs() < 1e-11,
            "{}",
            b.name()
        );
        assert!((sol.multipliers[0] - 1.0).abs() < 1e-11, "{}", b.name());
        assert_eq!(sol.multipliers[1], 0.0, "{}", b.name());
    }
}

#[test]
fn no_constraints_is_a_plain_solve() {
    let p = qp(
        2,
        &[(0, 0, 2.0), (0, 1, -1.0), (1, 0, -1.0), (1, 1, 2.0)],
        vec![1.0, 1.0],
        0,
        &[],
        vec![],
    );
    for mut b in backends() {
        let (sol, status) = solve(&mut b, &p, 1e-14);
        assert_eq!(status, QpStatus::Solved);
        assert!((sol.x[0] - 1.0).abs() < 1e-14 && (sol.x[1] - 1.0).abs() < 1e-14);
        assert!(sol.multipliers.is_empty());
    }
}

#[test]
fn contradicting_rows_are_reported_infeasible_without_panic() {
    // x ≤ −1 and −x ≤ −1 (x ≥ 1): no feasible point.
    let p = qp(
        1,
        &[(0, 0, 1.0)],
        vec![0.0],
        2,
        &[(0, 0, 1.0), (1, 0, -1.0)],
        vec![-1.0, -1.0],
    );
    for mut b in backends() {
        let (sol, status) = solve(&mut b, &p, 1e-9);
        assert_ne!(status, QpStatus::Solved, "{}", b.name());
        assert!(sol.x.iter().chain(&sol.multipliers).all(|v| v.is_finite()));
        // The backend's own verdict (checked_status may turn it into numerical-error when the
        // residuals of a meaningless x overflow).
        // Every backend, dual-ssn included, must give its own certificate.
        assert_eq!(
            sol.status,
            QpStatus::PrimalInfeasible,
            "{}: {:?}",
            b.name(),
            sol.message
        );
    }
}

#[test]
fn iteration_limit_is_a_status() {
    let p = common::laplacian_obstacle(30, 30, 20, 1.0);
    let options = SolveOptions {
        max_iter: Some(2),
        ..SolveOptions::default()
    };
    for mut b in [
        DualBackend::pgs(DualSettings::default()),
        DualBackend::uzawa(DualSettings::default()),
    ] {
        let sol = b.solve(&p, &options).unwrap();
        assert_eq!(sol.status, QpStatus::MaxIterations, "{}", b.name());
        assert_eq!(sol.iterations, 2);
    }
}

#[test]
fn bad_settings_are_an_error() {
    let p = qp(1, &[(0, 0, 2.0)], vec![4.0], 1, &[(0, 0, 1.0)], vec![1.0]);
    let settings = DualSettings {
        relaxation: 2.5,
        ..DualSettings::default()
    };
    assert!(DualBackend::pgs(settings)
        .solve(&p, &SolveOptions::default())
        .is_err());
}

#[test]
fn time_limit_is_a_status() {
    let p = common::laplacian_obstacle(30, 30, 20, 1.0);
    let options = SolveOptions {
        time_limit: Some(std::time::Duration::ZERO),
        ..SolveOptions::default()
    };
    for mut b in backends() {
        let sol = b.solve(&p, &options).unwrap();
        assert_eq!(sol.status, QpStatus::TimeLimit, "{}", b.name());
        assert!(sol.x.iter().all(|v| v.is_finite()));
    }
}

#[test]
fn nan_data_is_an_error_not_a_panic() {
    let mut p = qp(1, &[(0, 0, 2.0)], vec![4.0], 1, &[(0, 0, 1.0)], vec![1.0]);
    p.gap[0] = f64::NAN;
    for mut b in backends() {
        assert!(b.solve(&p, &SolveOptions::default()).is_err());
    }
}

/// 30 rows on a 25-node line: some rows are duplicated (a singular but consistent H), which the
/// active-set method must survive too.
#[test]
fn every_condensation_and_block_size_gives_the_same_answer() {
    use signorini_dual::Condensation;
    let p = common::laplacian_obstacle(25, 25, 30, 1.0);
    let mut reference: Option<Vec<f64>> = None;
    for condensation in [
        Condensation::TrailingBlock,
        Condensation::MultiRhs,
        Condensation::InteriorSchur,
    ] {
        for block_size in [1, 7, 64] {
            let mut b = DualBackend::active_set(DualSettings {
                condensation,
                block_size,
                ..DualSettings::default()
            });
            let (sol, status) = solve(&mut b, &p, 1e-10);
            assert_eq!(
                status,
                QpStatus::Solved,
                "{condensation:?} {block_size} {:?}",
                sol.message
            );
            match &reference {
                None => reference = Some(sol.x),
                Some(x) => assert!(common::rel_diff(x, &sol.x) < 1e-10),
            }
        }
    }
}
