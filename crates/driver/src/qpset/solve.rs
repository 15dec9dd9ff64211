//! Our backends on a set's problems, measured as qpbenchmark measures its solvers: one row per
//! problem × backend in qpbenchmark's results columns (`problem, solver, settings, runtime,
//! found, primal_residual, dual_residual, duality_gap`), with qpsolvers' residual definitions
//! (absolute: r_p = max(0, max(Gx − h)), r_d = ‖Px + q + Gᵀz‖∞, r_g = |xᵀPx + qᵀx + hᵀz|),
//! so that the two can be read side by side.  `found` is our own verdict: status `solved`
//! (the residuals of docs/scene.md meet the tolerance); an answer not found has infinite
//! residuals, as qpsolvers gives.

use std::path::{Path, PathBuf};
use std::time::Instant;

use signorini_core::qp::{
    checked_status, dot, kkt_residuals, mat_t_vec, mat_vec, QpProblem, QpStatus, SolveOptions,
};

use crate::backends::{make_backend, BackendKind};

use super::read::read_problem;
use super::QpsetError;

/// One backend on one problem.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RunRow {
    /// Problem name.
    pub problem: String,
    /// `signorini-BACKEND`.
    pub solver: String,
    /// The settings' name the row is filed under (qpbenchmark's `default`, `high_accuracy`).
    pub settings: String,
    /// Solve time, seconds.
    pub runtime: f64,
    /// Our status was `solved`.
    pub found: bool,
    /// max(0, max(Gx − h)).
    pub primal_residual: f64,
    /// ‖Px + q + Gᵀz‖∞.
    pub dual_residual: f64,
    /// |xᵀPx + qᵀx + hᵀz|.
    pub duality_gap: f64,
    /// Our status.
    pub status: String,
}

/// qpsolvers' three residuals of (x, z) for `min ½xᵀPx + qᵀx s.t. Gx ≤ h` with P = A, q = −f,
/// G = B, h = g.
pub fn qpsolvers_residuals(qp: &QpProblem, x: &[f64], z: &[f64]) -> (f64, f64, f64) {
    let gx = mat_vec(&qp.constraints, x);
    let primal = gx
        .iter()
        .zip(&qp.gap)
        .fold(0.0_f64, |m, (a, h)| m.max(a - h));
    let px = mat_vec(&qp.stiffness, x);
    let gtz = mat_t_vec(&qp.constraints, z);
    let dual = (0..x.len()).fold(0.0_f64, |m, j| m.max((px[j] - qp.load[j] + gtz[j]).abs()));
    let gap = (dot(x, &px) - dot(&qp.load, x) + dot(&qp.gap, z)).abs();
    (primal, dual, gap)
}

/// The `.npz` files of a set, sorted.
pub fn set_files(set: &Path) -> Result<Vec<PathBuf>, QpsetError> {
    let data = set.join("data");
    let entries = std::fs::read_dir(&data).map_err(|e| QpsetError::Dir {
        path: data.clone(),
        reason: e.to_string(),
    })?;
    let mut files: Vec<PathBuf> = entries
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "npz"))
        .collect();
    files.sort();
    Ok(files)
}

/// Runs every backend of `kinds` on every problem of the set at `set`; `progress` gets a line
/// per run.
pub fn run_set(
    set: &Path,
    kinds: &[BackendKind],
    settings: &str,
    options: &SolveOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<RunRow>, QpsetError> {
    let mut rows = Vec::new();
    for file in set_files(set)? {
        let problem = read_problem(&file)?;
        for &kind in kinds {
            let row = run_one(&problem.name, &problem.qp, kind, settings, options);
            progress(&format!(
                "{} {}: {} in {:.4} s",
                row.problem, row.solver, row.status, row.runtime
            ));
            rows.push(row);
        }
    }
    Ok(rows)
}

fn run_one(
    name: &str,
    qp: &QpProblem,
    kind: BackendKind,
    settings: &str,
    options: &SolveOptions,
) -> RunRow {
    let solver = format!("signorini-{kind}");
    let start = Instant::now();
    let answer = make_backend(kind).map(|mut b| b.solve(qp, options));
    let runtime = start.elapsed().as_secs_f64();
    let (status, found, residuals) = match answer {
        Ok(Ok(a)) if a.x.len() == qp.dofs() && a.multipliers.len() == qp.rows() => {
            let ours = kkt_residuals(qp, &a.x, &a.multipliers);
            let status = checked_status(a.status, &ours, options.tol);
            let found = status == QpStatus::Solved;
            let r = if found {
                qpsolvers_residuals(qp, &a.x, &a.multipliers)
            } else {
                (f64::INFINITY, f64::INFINITY, f64::INFINITY)
            };
            (status.to_string(), found, r)
        }
        Ok(Ok(a)) => (a.status.to_string(), false, infinite()),
        Ok(Err(e)) => (format!("error: {e}"), false, infinite()),
        Err(e) => (format!("error: {e}"), false, infinite()),
    };
    RunRow {
        problem: name.to_string(),
        solver,
        settings: settings.to_string(),
        runtime,
        found,
        primal_residual: residuals.0,
        dual_residual: residuals.1,
        duality_gap: residuals.2,
        status,
    }
}

fn infinite() -> (f64, f64, f64) {
    (f64::INFINITY, f64::INFINITY, f64::INFINITY)
}
