//! Spring chains: pressed against a wall (analytical answer) and a floating body held only by
//! contact (singular A with a known kernel).
#![allow(clippy::unwrap_used)]

mod common;

use common::{backends, qp, solve};
use signorini_qp::{QpBackend, QpProblem, QpStatus};

/// N nodes on a line, springs of stiffness k from a support to node 0 and between neighbours,
/// load p on every node toward a wall; row j: x_j ≤ (N − 1 − j) L + gap.
fn chain(nodes: usize, k: f64, p: f64, spacing: f64, gap: f64) -> QpProblem {
    let mut a = Vec::new();
    for j in 0..nodes {
        let diag = if j + 1 < nodes { 2.0 * k } else { k };
        a.push((j, j, diag));
        if j + 1 < nodes {
            a.push((j, j + 1, -k));
            a.push((j + 1, j, -k));
        }
    }
    let b: Vec<_> = (0..nodes).map(|j| (j, j, 1.0)).collect();
    let g = (0..nodes)
        .map(|j| (nodes - 1 - j) as f64 * spacing + gap)
        .collect();
    qp(nodes, &a, vec![p; nodes], nodes, &b, g)
}

#[test]
fn chain_pressed_against_a_wall_matches_the_analytical_answer() {
    let (n, k, p, gap) = (50, 1e3, 2.0, 0.5);
    let problem = chain(n, k, p, 1.0, gap);
    // Spring i (support → node 0 is i = 0) carries p (n − i) − λ; the last node touches the wall.
    let free_tip: f64 = (0..n).map(|i| p * (n - i) as f64 / k).sum();
    assert!(free_tip > gap);
    let reaction = k * (free_tip - gap) / n as f64;
    let mut expected = Vec::with_capacity(n);
    let mut x = 0.0;
    for i in 0..n {
        x += (p * (n - i) as f64 - reaction) / k;
        expected.push(x);
    }
    for mut b in backends() {
        let (sol, status) = solve(&mut b, &problem, 1e-10);
        assert_eq!(status, QpStatus::Solved, "{}: {:?}", b.name(), sol.message);
        let err = common::rel_diff(&expected, &sol.x);
        assert!(err < 1e-8, "{}: x error {err:e}", b.name());
        assert!((sol.multipliers[n - 1] - reaction).abs() < 1e-8 * reaction);
        assert!(
            sol.multipliers[..n - 1].iter().all(|l| *l == 0.0),
            "{}",
            b.name()
        );
    }
}

/// Body 1: DOF 0 held by a ground spring k1.  Body 2: DOFs 1, 2, 3 joined by springs k2, free
/// (kernel r = (0, 1, 1, 1)).  Contact: x0 − x1 ≤ gap (body 2's left end cannot pass body 1's
/// right end).  Load `push` on DOF 3 (negative = toward body 1).
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

#[test]
fn floating_body_held_only_by_contact() {
    let p = 3.0;
    let problem = floating(-p);
    let (k1, k2, gap) = (10.0, 4.0, 0.1);
    let x0 = -p / k1;
    let x1 = x0 - gap;
    let expected = [x0, x1, x1 - p / k2, x1 - 2.0 * p / k2];
    for mut b in backends() {
        let (sol, status) = solve(&mut b, &problem, 1e-10);
        assert_eq!(status, QpStatus::Solved, "{}: {:?}", b.name(), sol.message);
        let err = common::rel_diff(&expected, &sol.x);
        assert!(err < 1e-9, "{}: {:?} vs {expected:?}", b.name(), sol.x);
        assert!((sol.multipliers[0] - p).abs() < 1e-9, "{}", b.name());
    }
}

/// A floating body pushed away from its only contact: the objective is unbounded below, and the
/// backend must say so itself (dual infeasible), with finite numbers.
fn check_pushed_away(mut b: signorini_dual::DualBackend) {
    let problem = floating(3.0);
    let (sol, status) = solve(&mut b, &problem, 1e-10);
    assert_ne!(status, QpStatus::Solved, "{}", b.name());
    assert!(sol.x.iter().chain(&sol.multipliers).all(|v| v.is_finite()));
    assert_eq!(
        sol.status,
        QpStatus::DualInfeasible,
        "{}: {:?}",
        b.name(),
        sol.message
    );
}

#[test]
fn floating_body_pushed_away_is_unbounded_not_nan() {
    for b in backends().into_iter().filter(|b| b.name() != "dual-ssn") {
        check_pushed_away(b);
    }
}

/// The same for dual-ssn.  Regression (issue 9): it used to report `numerical-error`
/// ("singular active-set system on 0 rows …") instead of detecting the unbounded direction; it
/// now checks up front whether any λ ≥ 0 balances the load on the rigid modes.
#[test]
fn floating_body_pushed_away_is_unbounded_for_dual_ssn() {
    for b in backends().into_iter().filter(|b| b.name() == "dual-ssn") {
        check_pushed_away(b);
    }
}

#[test]
fn singular_stiffness_without_kernel_is_a_numerical_error() {
    let mut problem = floating(-3.0);
    problem.kernel.clear();
    for mut b in backends() {
        let (sol, status) = solve(&mut b, &problem, 1e-10);
        assert_eq!(status, QpStatus::NumericalError, "{}", b.name());
        assert!(sol.x.iter().all(|v| v.is_finite()));
        let message = sol.message.unwrap_or_default();
        assert!(message.contains("singular"), "{message}");
    }
}
