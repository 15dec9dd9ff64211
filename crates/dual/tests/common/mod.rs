//! Builders shared by the integration tests.
#![allow(dead_code, unused_imports, clippy::unwrap_used)]

use signorini_dual::{DualBackend, DualSettings};
use signorini_qp::{
    checked_status, kkt_residuals, QpBackend, QpProblem, QpSolution, QpStatus, SolveOptions,
};

pub use signorini_qp::examples::csc_from_triplets as csc;

/// A QP from triplets.
pub fn qp(
    n: usize,
    a: &[(usize, usize, f64)],
    f: Vec<f64>,
    m: usize,
    b: &[(usize, usize, f64)],
    g: Vec<f64>,
) -> QpProblem {
    signorini_qp::examples::qp_from_triplets(n, a, f, m, b, g).unwrap()
}

/// The three dual backends with default settings.
pub fn backends() -> Vec<DualBackend> {
    vec![
        DualBackend::pgs(DualSettings::default()),
        DualBackend::uzawa(DualSettings::default()),
        DualBackend::active_set(DualSettings::default()),
    ]
}

/// Solves and returns the solution with the checked status.
pub fn solve(backend: &mut DualBackend, problem: &QpProblem, tol: f64) -> (QpSolution, QpStatus) {
    let options = SolveOptions {
        tol,
        ..SolveOptions::default()
    };
    let sol = backend.solve(problem, &options).unwrap();
    let r = kkt_residuals(problem, &sol.x, &sol.multipliers);
    let status = checked_status(sol.status, &r, tol);
    (sol, status)
}

/// 5-point Laplacian on an nx × ny grid (Dirichlet outside), scaled by `stiffness`, with a
/// downward load and bound rows x_i ≤ −depth on the `rows` nodes of the middle grid line.
pub fn laplacian_obstacle(nx: usize, ny: usize, rows: usize, stiffness: f64) -> QpProblem {
    let n = nx * ny;
    let id = |i: usize, j: usize| j * nx + i;
    let mut a = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let k = id(i, j);
            a.push((k, k, 4.0 * stiffness));
            if i + 1 < nx {
                a.push((k, id(i + 1, j), -stiffness));
                a.push((id(i + 1, j), k, -stiffness));
            }
            if j + 1 < ny {
                a.push((k, id(i, j + 1), -stiffness));
                a.push((id(i, j + 1), k, -stiffness));
            }
        }
    }
    let f = vec![-stiffness / (n as f64); n];
    let line = ny / 2;
    let mut b = Vec::new();
    let mut g = Vec::new();
    for r in 0..rows {
        let i = (r * nx) / rows + nx / (2 * rows);
        // −x ≤ depth(i): the obstacle from below, a bump in the middle.
        b.push((r, id(i.min(nx - 1), line), -1.0));
        let s = (i as f64 + 0.5) / nx as f64 - 0.5;
        g.push(0.02 + 0.2 * s * s);
    }
    QpProblem::try_new(csc(n, n, &a), f, csc(rows, n, &b), g).unwrap()
}

/// max |x − reference| / max |reference| (the reference first, as these tests write it).
pub fn rel_diff(reference: &[f64], x: &[f64]) -> f64 {
    signorini_qp::examples::rel_diff(x, reference)
}
