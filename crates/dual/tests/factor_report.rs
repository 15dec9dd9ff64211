//! The solution message names the factor's ordering and size (issue 9: the dual solvers use the
//! floor's ordering path, `signorini_qp::linalg::fill_reducing_order`, and report it).
#![allow(clippy::unwrap_used)]

mod common;

use common::{backends, qp, solve};
use signorini_qp::linalg::fill_reducing_order;
use signorini_qp::{QpBackend, QpStatus};

/// A = diag(2, …, 2) (5 DOFs), one row on DOF 2: L is diagonal whatever the ordering, so it has
/// exactly 5 stored entries (one 1 × 1 supernode per column, nothing below the diagonal).
#[test]
fn message_names_the_ordering_and_nnz_of_l() {
    let a: Vec<_> = (0..5).map(|i| (i, i, 2.0)).collect();
    let p = qp(5, &a, vec![4.0; 5], 1, &[(0, 2, 1.0)], vec![1.0]);
    let method = fill_reducing_order(&p.stiffness).unwrap().method;
    for mut b in backends() {
        let (sol, status) = solve(&mut b, &p, 1e-12);
        assert_eq!(status, QpStatus::Solved, "{}", b.name());
        let message = sol.message.unwrap();
        let expected = format!("ordering {method}, nnz(L) 5.000e0");
        assert!(message.contains(&expected), "{}: {message}", b.name());
    }
}

/// Issue 21: a dual method that stops short says why it may have: A's conditioning, which the
/// condensed dual inherits, as the factor's smallest pivot ratio.  A = [1, 1 − ε; 1 − ε, 1]:
/// L₁₁² = 1, L₂₂² = 1 − (1 − ε)² = 2ε − ε², so the ratio is 2.0e-6 at ε = 1e-6 (Jacobi
/// scaling leaves this unit diagonal alone).  One projected Gauss–Seidel sweep cannot meet
/// 1e-12 on it; with the default cap it is solved, and the message stays as it was.
#[test]
fn a_method_that_stops_short_names_a_s_smallest_pivot_ratio() {
    use signorini_dual::{DualBackend, DualSettings};
    let e = 1e-6;
    let a = [(0, 0, 1.0), (0, 1, 1.0 - e), (1, 0, 1.0 - e), (1, 1, 1.0)];
    let p = qp(
        2,
        &a,
        vec![1.0, 0.5],
        2,
        &[(0, 0, 1.0), (1, 1, 1.0)],
        vec![0.1, 0.1],
    );
    let mut capped = DualBackend::pgs(DualSettings {
        max_iter: 1,
        ..DualSettings::default()
    });
    let (sol, status) = solve(&mut capped, &p, 1e-12);
    assert_ne!(status, QpStatus::Solved);
    let message = sol.message.unwrap();
    assert!(
        message.contains("A's smallest Cholesky pivot ratio minⱼ Lⱼⱼ²/Aⱼⱼ = 2.0e-6"),
        "{message}"
    );
    let (sol, status) = solve(
        &mut DualBackend::active_set(DualSettings::default()),
        &p,
        1e-12,
    );
    assert_eq!(status, QpStatus::Solved);
    assert!(!sol.message.unwrap().contains("pivot ratio"));
}
