//! No dense cliff (issue 9): dual-ssn's matrix-free Newton steps (projected CG through the
//! sparse factor) give the answers of the dense ones, and a problem whose dense H cannot fit in
//! memory is solved by dual-ssn without forming it, while dual-pgs (which needs the columns of
//! H) refuses with `TooLarge` (a resource refusal: exit 3 from `solve`) instead of allocating.
#![allow(clippy::unwrap_used)]

mod common;

use common::{laplacian_obstacle, qp, rel_diff, solve};
use signorini_dual::{DualBackend, DualSettings};
use signorini_qp::memory::available_bytes;
use signorini_qp::{QpBackend, QpError, QpProblem, QpStatus, SolveOptions};

fn matrix_free() -> DualBackend {
    DualBackend::active_set(DualSettings {
        matrix_free_rows: 0,
        ..DualSettings::default()
    })
}

/// The same answer with and without the dense H.  Both meet the KKT residuals to 1e-10; for this
/// Laplacian (condition ~1e3) that bounds the difference of the two x by ~1e3 · 1e-10 = 1e-7.
#[test]
fn matrix_free_newton_steps_agree_with_dense_ones() {
    let p = laplacian_obstacle(60, 60, 40, 1.0);
    let (dense, s1) = solve(
        &mut DualBackend::active_set(DualSettings::default()),
        &p,
        1e-10,
    );
    let (free, s2) = solve(&mut matrix_free(), &p, 1e-10);
    assert_eq!(s1, QpStatus::Solved, "{:?}", dense.message);
    assert_eq!(s2, QpStatus::Solved, "{:?}", free.message);
    assert!(free.message.as_deref().unwrap().contains("matrix-free"));
    assert!(rel_diff(&dense.x, &free.x) < 1e-7);
    assert!(rel_diff(&dense.multipliers, &free.multipliers) < 1e-7);
}

/// A floating body held only by contact (kernel r = (0, 1, 1, 1)): the projected CG keeps the
/// equality G λ = e; the answer is the hand-computed one of tests/springs.rs.
#[test]
fn matrix_free_handles_the_rigid_mode_equality() {
    let (k1, k2, gap, p) = (10.0, 4.0, 0.1, 3.0);
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
    let problem = qp(
        4,
        &a,
        vec![0.0, 0.0, 0.0, -p],
        1,
        &[(0, 0, 1.0), (0, 1, -1.0)],
        vec![gap],
    )
    .with_kernel(vec![vec![0.0, 1.0, 1.0, 1.0]])
    .unwrap();
    let x0 = -p / k1;
    let x1 = x0 - gap;
    let expected = [x0, x1, x1 - p / k2, x1 - 2.0 * p / k2];
    let (sol, status) = solve(&mut matrix_free(), &problem, 1e-10);
    assert_eq!(status, QpStatus::Solved, "{:?}", sol.message);
    // Exact data, a 1-row dual: round-off only.
    assert!(rel_diff(&expected, &sol.x) < 1e-12, "{:?}", sol.x);
    assert!((sol.multipliers[0] - p).abs() < 1e-12);
}

/// n = m = 200 000: A = diag(2), B = I, g = 1, f alternating ±4 → x = min(f/2, 1) per DOF,
/// λ = max(f − 2, 0).  The dense H would take 8 m² = 320 GB.
fn huge_diagonal() -> QpProblem {
    let n = 200_000;
    let a: Vec<_> = (0..n).map(|i| (i, i, 2.0)).collect();
    let b: Vec<_> = (0..n).map(|i| (i, i, 1.0)).collect();
    let f = (0..n)
        .map(|i| if i % 2 == 0 { 4.0 } else { -4.0 })
        .collect();
    qp(n, &a, f, n, &b, vec![1.0; n])
}

fn dense_cannot_fit() -> bool {
    available_bytes().is_some_and(|bytes| (bytes as f64) < 8.0 * 2e5 * 2e5)
}

#[test]
fn dual_ssn_solves_without_forming_a_dense_h_that_cannot_fit() {
    if !dense_cannot_fit() {
        return;
    }
    let p = huge_diagonal();
    let (sol, status) = solve(
        &mut DualBackend::active_set(DualSettings::default()),
        &p,
        1e-10,
    );
    assert_eq!(status, QpStatus::Solved, "{:?}", sol.message);
    assert!(sol.message.as_deref().unwrap().contains("matrix-free"));
    for (i, (x, l)) in sol.x.iter().zip(&sol.multipliers).enumerate() {
        let (x_ref, l_ref) = if i % 2 == 0 { (1.0, 2.0) } else { (-2.0, 0.0) };
        assert!(
            (x - x_ref).abs() < 1e-12 && (l - l_ref).abs() < 1e-12,
            "{i}: {x} {l}"
        );
    }
}

#[test]
fn dual_pgs_refuses_when_h_cannot_fit_instead_of_allocating() {
    if !dense_cannot_fit() {
        return;
    }
    let p = huge_diagonal();
    let err = DualBackend::pgs(DualSettings::default())
        .solve(&p, &SolveOptions::default())
        .unwrap_err();
    // The machine's memory, not the scene, is at fault: `TooLarge`, which `solve` maps to
    // exit 3 (it was `Unavailable`, exit 1, as if the input were bad).
    match &err {
        QpError::TooLarge { backend, what, .. } => {
            assert_eq!(*backend, "dual-pgs");
            assert!(
                what.contains("200000 × 200000") && what.contains("dual-ssn"),
                "{err}"
            );
        }
        other => panic!("expected TooLarge, got {other}"),
    }
}
