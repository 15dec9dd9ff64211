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
