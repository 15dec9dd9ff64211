//! A 2-D Laplacian-like SPD problem (n ≈ 2000, 40 bound rows): every method reaches the same
//! answer, meets the KKT tolerance, and an equivalent badly scaled problem gives the same x.
#![allow(clippy::unwrap_used)]

mod common;

use common::{backends, laplacian_obstacle, rel_diff, solve};
use signorini_dual::{Condensation, DualBackend, DualSettings};
use signorini_qp::{QpBackend, QpStatus};

#[test]
fn methods_agree_and_meet_the_tolerance() {
    let problem = laplacian_obstacle(45, 45, 40, 1.0);
    let tol = 1e-9;
    let mut answers = Vec::new();
    for mut b in backends() {
        let (sol, status) = solve(&mut b, &problem, tol);
        assert_eq!(status, QpStatus::Solved, "{}: {:?}", b.name(), sol.message);
        let active = sol.multipliers.iter().filter(|l| **l > 0.0).count();
        assert!(
            active > 0 && active < 40,
            "{}: {active} active rows",
            b.name()
        );
        answers.push((b.name(), sol));
    }
    let (_, reference) = &answers[0];
    for (name, sol) in &answers[1..] {
        assert!(rel_diff(&reference.x, &sol.x) < 1e-8, "{name} x");
        assert!(
            rel_diff(&reference.multipliers, &sol.multipliers) < 1e-8,
            "{name} λ"
        );
    }
}

#[test]
fn badly_scaled_equivalent_gives_the_same_x() {
    let tol = 1e-9;
    let unit = laplacian_obstacle(45, 45, 40, 1.0);
    let stiff = laplacian_obstacle(45, 45, 40, 1e11);
    for mut b in backends() {
        let (a, sa) = solve(&mut b, &unit, tol);
        let (c, sc) = solve(&mut b, &stiff, tol);
        assert_eq!(
            (sa, sc),
            (QpStatus::Solved, QpStatus::Solved),
            "{}",
            b.name()
        );
        assert!(rel_diff(&a.x, &c.x) < 1e-8, "{}", b.name());
        let scaled: Vec<f64> = a.multipliers.iter().map(|l| l * 1e11).collect();
        assert!(rel_diff(&scaled, &c.multipliers) < 1e-8, "{}", b.name());
    }
}

#[test]
fn both_condensations_give_the_same_answer() {
    let problem = laplacian_obstacle(30, 30, 25, 1.0);
    let mut xs = Vec::new();
    for condensation in [Condensation::MultiRhs, Condensation::InteriorSchur] {
        let mut b = DualBackend::pgs(DualSettings {
            condensation,
            block_size: 7,
            ..DualSettings::default()
        });
        let (sol, status) = solve(&mut b, &problem, 1e-10);
        assert_eq!(status, QpStatus::Solved, "{condensation:?}");
        xs.push(sol.x);
    }
    assert!(rel_diff(&xs[0], &xs[1]) < 1e-9);
}

#[test]
fn plain_uzawa_and_relaxed_pgs_converge_too() {
    let problem = laplacian_obstacle(20, 20, 15, 1.0);
    for mut b in [
        DualBackend::uzawa(DualSettings {
            accelerate: false,
            step_factor: 1.9,
            ..DualSettings::default()
        }),
        DualBackend::pgs(DualSettings {
            relaxation: 1.5,
            ..DualSettings::default()
        }),
    ] {
        let (sol, status) = solve(&mut b, &problem, 1e-9);
        assert_eq!(status, QpStatus::Solved, "{}: {:?}", b.name(), sol.message);
        eprintln!("{}: {} iterations", b.name(), sol.iterations);
    }
}
