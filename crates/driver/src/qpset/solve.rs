//! Our backends on a set's problems, measured as qpbenchmark measures its solvers: one row per
//! problem × backend in qpbenchmark's results columns (`problem, solver, settings, runtime,
//! found, primal_residual, dual_residual, duality_gap`), with qpsolvers' residual definitions
//! (absolute: r_p = max(0, max(Gx − h)), r_d = ‖Px + q + Gᵀz‖∞, r_g = |xᵀPx + qᵀx + hᵀz|),
//! so that the two can be read side by side.  `found` is our own verdict: status `solved`
//! (the residuals of docs/scene.md meet the tolerance); an answer not found has infinite
//! residuals, as qpsolvers gives.  The settings name decides the run as it decides qpbenchmark's:
//! `default` solves at our tolerance; `high_accuracy` (and `mid_`, `low_accuracy`) gives the
//! backends qpbenchmark's absolute target `eps_abs` (1e-9; 1e-6, 1e-3), met by tightening our
//! relative tolerance until qpsolvers' three residuals are below it.

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
    /// Our status was `solved` — and, under a settings with an absolute tolerance ε
    /// ([`settings_eps_abs`]: qpbenchmark's `eps_abs`), qpsolvers' three residuals were at most
    /// ε, the backend's relative tolerance tightened until they were (or [`TOL_FLOOR`]).
    pub found: bool,
    /// max(0, max(Gx − h)).
    pub primal_residual: f64,
    /// ‖Px + q + Gᵀz‖∞.
    pub dual_residual: f64,
    /// |xᵀPx + qᵀx + hᵀz|.
    pub duality_gap: f64,
    /// Our status.
    pub status: String,
    /// The relative KKT tolerance of the last attempt.
    pub tolerance: f64,
    /// Why the last attempt was not `solved`: the backend's own message (empty when solved,
    /// or when `status` holds the error itself).  Not a qpbenchmark column.
    #[serde(skip)]
    pub why: String,
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

/// qpbenchmark's absolute tolerance `eps_abs` of a settings name (its solvers run with it and
/// `eps_rel = 0`; `qpbenchmark.TestSet.define_solver_settings`, 2.7), `None` for `default`
/// (each solver's own defaults) and any other name.
pub fn settings_eps_abs(settings: &str) -> Option<f64> {
    match settings {
        "high_accuracy" => Some(1e-9),
        "mid_accuracy" => Some(1e-6),
        "low_accuracy" => Some(1e-3),
        _ => None,
    }
}

/// The tightest relative tolerance an absolute target drives a backend to: a few hundred ε,
/// below which our relative KKT measures are round-off.
pub const TOL_FLOOR: f64 = 1e-14;

/// Runs every backend of `kinds` on every problem of the set at `set`; `progress` gets a line
/// per run.  Under a settings with an absolute tolerance ([`settings_eps_abs`]) each backend is
/// driven to it: see [`RunRow::found`].
pub fn run_set(
    set: &Path,
    kinds: &[BackendKind],
    settings: &str,
    options: &SolveOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<RunRow>, QpsetError> {
    let eps_abs = settings_eps_abs(settings);
    let mut rows = Vec::new();
    for file in set_files(set)? {
        let problem = read_problem(&file)?;
        for &kind in kinds {
            let mut row = run_one(&problem.qp, kind, options, eps_abs);
            row.problem.clone_from(&problem.name);
            row.settings = settings.to_string();
            let why = if row.why.is_empty() {
                String::new()
            } else {
                format!(": {}", row.why)
            };
            progress(&format!(
                "{} {}: {} in {:.4} s (tolerance {:.0e}){why}",
                row.problem, row.solver, row.status, row.runtime, row.tolerance
            ));
            rows.push(row);
        }
    }
    Ok(rows)
}

/// One backend on one problem at `options.tol`; with `eps_abs`, solved again at a tighter
/// relative tolerance while qpsolvers' absolute residuals miss it (down to [`TOL_FLOOR`], within
/// the time limit counted over every attempt).
fn run_one(
    qp: &QpProblem,
    kind: BackendKind,
    options: &SolveOptions,
    eps_abs: Option<f64>,
) -> RunRow {
    let start = Instant::now();
    let mut tol = options.tol;
    loop {
        let mut attempt = options.clone();
        attempt.tol = tol;
        if let Some(limit) = options.time_limit {
            attempt.time_limit = Some(limit.saturating_sub(start.elapsed()));
        }
        let (status, residuals, why) = attempt_once(qp, kind, &attempt);
        let found = status == QpStatus::Solved.as_str();
        let worst = residuals.0.max(residuals.1).max(residuals.2);
        let (found, status, why) = match eps_abs {
            Some(eps) if found && worst > eps => {
                if tol > TOL_FLOOR && !out_of_time(options, start) {
                    tol = (0.1 * tol * eps / worst).clamp(TOL_FLOOR, 0.1 * tol);
                    continue;
                }
                // The status says why; the backend's message would say `solved`.
                (
                    false,
                    format!("inaccurate (absolute residual {worst:.1e} > {eps:.0e})"),
                    String::new(),
                )
            }
            _ => (found, status, why),
        };
        let r = if found { residuals } else { infinite() };
        return RunRow {
            problem: String::new(),
            solver: format!("signorini-{kind}"),
            settings: String::new(),
            runtime: start.elapsed().as_secs_f64(),
            found,
            primal_residual: r.0,
            dual_residual: r.1,
            duality_gap: r.2,
            why: if found { String::new() } else { why },
            status,
            tolerance: tol,
        };
    }
}

fn out_of_time(options: &SolveOptions, start: Instant) -> bool {
    options
        .time_limit
        .is_some_and(|limit| start.elapsed() >= limit)
}

/// One solve: our checked status, qpsolvers' residuals when `solved` (else infinite), and the
/// backend's message.
fn attempt_once(
    qp: &QpProblem,
    kind: BackendKind,
    options: &SolveOptions,
) -> (String, (f64, f64, f64), String) {
    match make_backend(kind).map(|mut b| b.solve(qp, options)) {
        Ok(Ok(a)) if a.x.len() == qp.dofs() && a.multipliers.len() == qp.rows() => {
            let ours = kkt_residuals(qp, &a.x, &a.multipliers);
            let status = checked_status(a.status, &ours, options.tol);
            let r = if status == QpStatus::Solved {
                qpsolvers_residuals(qp, &a.x, &a.multipliers)
            } else {
                infinite()
            };
            (status.to_string(), r, a.message.unwrap_or_default())
        }
        Ok(Ok(a)) => (
            a.status.to_string(),
            infinite(),
            format!(
                "{} (an answer of the wrong size: x {}, λ {})",
                a.message.unwrap_or_default(),
                a.x.len(),
                a.multipliers.len()
            ),
        ),
        Ok(Err(e)) => (format!("error: {e}"), infinite(), String::new()),
        Err(e) => (format!("error: {e}"), infinite(), String::new()),
    }
}

fn infinite() -> (f64, f64, f64) {
    (f64::INFINITY, f64::INFINITY, f64::INFINITY)
}
