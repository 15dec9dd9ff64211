//! Plots of a sweep (`sweep.csv`, written by `signorini sweep`) as SVG files.
//!
//! * [`read_sweep`] parses the CSV into [`SweepRow`]s (columns are matched by header name, so
//!   their order does not matter; a bad field is reported with the file, line and column).
//! * [`fit_slope`] fits `y ≈ C·x^p` by least squares in log–log space and returns `p`.
//! * [`plot_sweep`] writes up to four SVGs into a directory (see its docs):
//!   `time_vs_dofs.svg`, `ratio_vs_dofs.svg`, `work_precision.svg`, `iterations_vs_dofs.svg`.
//!
//! Conventions shared by the plots: every axis is logarithmic; each backend keeps one colour and
//! one marker shape across all plots (in order of first appearance in the CSV); only rows whose
//! status is `solved` are joined by the curves, other rows are drawn as hollow markers of the
//! backend's colour; values that cannot be shown on a log axis (zero, negative, NaN, empty) are
//! left out, except that a zero error on the work–precision plot is clamped to [`ERROR_FLOOR`]
//! (the legend says so).  The files are written as one set (see [`crate::outdir`]).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Deserializer};

use crate::output::OutputError;

pub(crate) mod render;

use render::{Curve, Figure};

/// Errors equal to zero are drawn at this value on the (logarithmic) work–precision plot.
pub const ERROR_FLOOR: f64 = 1e-16;

/// One row of `sweep.csv`: one (hmax, backend, tolerance) point of a sweep.
///
/// Required floating-point columns may be empty in the file; they then read as NaN (and such a
/// point is left out of the plots that need it).
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct SweepRow {
    /// Largest element size of the mesh.
    #[serde(deserialize_with = "f64_or_nan")]
    pub hmax: f64,
    /// Number of degrees of freedom of the QP.
    pub dofs: usize,
    /// Number of contact constraints of the QP.
    pub constraints: usize,
    /// Backend name (e.g. `clarabel`, `osqp`, `dual-pgs`, `dual-uzawa`).
    pub backend: String,
    /// Tolerance the backend was run with.
    #[serde(deserialize_with = "f64_or_nan")]
    pub tol: f64,
    /// Solver status (`solved`, `inaccurate`, `max-iterations`, …).
    pub status: String,
    /// Iterations the backend reported.
    pub iterations: usize,
    /// Meshing time in seconds.
    #[serde(deserialize_with = "f64_or_nan")]
    pub mesh_s: f64,
    /// Assembly time in seconds.
    #[serde(deserialize_with = "f64_or_nan")]
    pub assemble_s: f64,
    /// QP solve time in seconds.
    #[serde(deserialize_with = "f64_or_nan")]
    pub solve_s: f64,
    /// The floor in seconds: one unconstrained factorisation + solve of the stiffness matrix
    /// (the same for all rows of an hmax).
    #[serde(deserialize_with = "f64_or_nan")]
    pub floor_s: f64,
    /// `solve_s / floor_s`.
    #[serde(deserialize_with = "f64_or_nan")]
    pub ratio_to_floor: f64,
    /// Error of the displacement against the reference solution (empty if not computed).
    pub error_vs_reference: Option<f64>,
    /// Error against the finest mesh of the sweep (empty if not computed).
    pub error_vs_finest: Option<f64>,
    /// Largest nodal displacement norm.
    #[serde(deserialize_with = "f64_or_nan")]
    pub max_displacement: f64,
    /// Peak resident set size in MB.
    #[serde(deserialize_with = "f64_or_nan")]
    pub peak_rss_mb: f64,
    /// Largest constraint violation (penetration) of the solution.
    #[serde(deserialize_with = "f64_or_nan")]
    pub max_penetration: f64,
    /// KKT stationarity residual.
    #[serde(deserialize_with = "f64_or_nan")]
    pub stationarity: f64,
    /// KKT complementarity residual.
    #[serde(deserialize_with = "f64_or_nan")]
    pub complementarity: f64,
}

impl SweepRow {
    /// Whether the backend reported success.
    fn solved(&self) -> bool {
        self.status.trim().eq_ignore_ascii_case("solved")
    }
}

/// A float column that may be empty (read as NaN).
fn f64_or_nan<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// Reads `sweep.csv`: a header row, then one row per point.  Columns are matched by name
/// (extra columns are ignored), surrounding blanks are trimmed, blank lines are skipped.
///
/// Errors ([`OutputError::Mismatch`]) name the file, and for a bad row its line number and the
/// offending column, e.g. `sweep.csv, line 7, column "dofs": invalid digit found in string`.
pub fn read_sweep(path: &Path) -> Result<Vec<SweepRow>, OutputError> {
    let name = path.display();
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_path(path)
        .map_err(|e| OutputError::Mismatch(format!("cannot read {name}: {e}")))?;
    let headers = reader
        .headers()
        .map_err(|e| OutputError::Mismatch(format!("{name}, line 1 (header): {e}")))?
        .clone();
    let mut rows = Vec::new();
    let mut record = csv::StringRecord::new();
    loop {
        let more = reader
            .read_record(&mut record)
            .map_err(|e| OutputError::Mismatch(describe_csv_error(&name, &e)))?;
        if !more {
            break;
        }
        let line = record.position().map_or(0, csv::Position::line);
        let row: SweepRow = record.deserialize(Some(&headers)).map_err(|e| {
            let what = match e.kind() {
                csv::ErrorKind::Deserialize { err, .. } => {
                    let column = err
                        .field()
                        .and_then(|i| headers.get(i as usize))
                        .map(|h| format!(", column \"{h}\""))
                        .unwrap_or_default();
                    format!("{column}: {}", err.kind())
                }
                _ => format!(": {e}"),
            };
            OutputError::Mismatch(format!("{name}, line {line}{what}"))
        })?;
        rows.push(row);
    }
    Ok(rows)
}

/// Message for a CSV reading error (I/O, bad UTF-8, wrong number of fields), with its line.
fn describe_csv_error(name: &std::path::Display, e: &csv::Error) -> String {
    match e.kind() {
        csv::ErrorKind::UnequalLengths {
            pos,
            expected_len,
            len,
        } => {
            let line = pos.as_ref().map_or(0, csv::Position::line);
            format!("{name}, line {line}: {len} fields, but the header has {expected_len}")
        }
        _ => match e.position() {
            Some(pos) => format!("{name}, line {}: {e}", pos.line()),
            None => format!("{name}: {e}"),
        },
    }
}

/// Least-squares slope of `ln y` against `ln x`: the exponent `p` of the best fit `y ≈ C·x^p`.
///
/// Points with a non-positive or non-finite coordinate are ignored.  Returns `None` when fewer
/// than two distinct `x` remain.
pub fn fit_slope(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = logs.len() as f64;
    let mx = logs.iter().map(|p| p.0).sum::<f64>() / n;
    let my = logs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = logs.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let distinct = logs.iter().any(|p| p.0 != logs[0].0);
    (logs.len() >= 2 && distinct && sxx > 0.0).then(|| sxy / sxx)
}

/// File names of the sweep plots, in the order [`render_sweep`] returns them.
pub const PLOT_FILES: [&str; 4] = [
    "time_vs_dofs.svg",
    "ratio_vs_dofs.svg",
    "work_precision.svg",
    "iterations_vs_dofs.svg",
];

/// Writes the sweep plots into `dir` (created if missing) and returns the paths written, in the
/// order below.  `title` prefixes each plot's heading (it may be empty, and may hold any text:
/// characters XML forbids become U+FFFD, the rest is escaped).
///
/// 1. `time_vs_dofs.svg`: solve time (`solve_s`) against DOFs, one curve per backend from its
///    tightest-tolerance row at each hmax, plus the floor (`floor_s`) dashed black; every
///    legend entry carries the fitted [`fit_slope`] exponent, e.g. `dual-pgs (slope 1.08)`.
/// 2. `ratio_vs_dofs.svg`: `ratio_to_floor` (or `solve_s / floor_s` if that column is empty)
///    against DOFs, same rows and slopes as 1, with a dashed grey reference line at 1.
/// 3. `work_precision.svg`: `error_vs_reference` against solve time, one curve per backend
///    joining its tolerances, at the finest (smallest) hmax of the file (named in the heading
///    with its DOFs).  Errors equal to 0 are drawn at [`ERROR_FLOOR`] (the legend says so).
///    No slopes here (error against time is no power law).  Skipped unless that hmax has at
///    least two distinct tolerances with an error.
/// 4. `iterations_vs_dofs.svg`: iterations against DOFs (log–log; rows with 0 iterations are
///    left out), same rows and slopes as 1.
///
/// A plot without any drawable backend point is skipped.  The plots are one output set (see
/// [`crate::outdir`]): written together under the directory's lock, and a plot of an earlier
/// call that this one skips is removed, so the directory never mixes plots of two sweeps.  An
/// empty `rows` (nothing drawable) touches nothing and returns an empty list.
pub fn plot_sweep(rows: &[SweepRow], dir: &Path, title: &str) -> Result<Vec<PathBuf>, OutputError> {
    let plots = render_sweep(rows, title)?;
    if plots.is_empty() {
        return Ok(Vec::new());
    }
    let lock = crate::outdir::DirLock::acquire(dir)?;
    let mut set = crate::outdir::OutputSet::new(&lock, None, &PLOT_FILES)?;
    for (name, svg) in &plots {
        set.write(name, |w| w.write_all(svg.as_bytes()))?;
    }
    set.commit()
}

/// The plots of [`plot_sweep`] as `(file name, SVG document)`, without writing anything.
pub fn render_sweep(
    rows: &[SweepRow],
    title: &str,
) -> Result<Vec<(&'static str, String)>, OutputError> {
    let backends = backend_order(rows);
    let figures = [
        time_vs_dofs(rows, &backends, title),
        ratio_vs_dofs(rows, &backends, title),
        work_precision(rows, &backends, title),
        iterations_vs_dofs(rows, &backends, title),
    ];
    let mut plots = Vec::new();
    for (file, figure) in PLOT_FILES.into_iter().zip(figures) {
        let Some(figure) = figure else { continue };
        if let Some(svg) = render::render(&figure)? {
            plots.push((file, svg));
        }
    }
    Ok(plots)
}

/// Backend names in order of first appearance.
fn backend_order(rows: &[SweepRow]) -> Vec<&str> {
    let mut names: Vec<&str> = Vec::new();
    for r in rows {
        if !names.contains(&r.backend.as_str()) {
            names.push(&r.backend);
        }
    }
    names
}

/// Heading of a plot: `"{title}: {what}"`, or just `what` without a title.
fn heading(title: &str, what: &str) -> String {
    if title.trim().is_empty() {
        what.to_string()
    } else {
        format!("{title}: {what}")
    }
}

/// Key of an hmax value (exact: rows of one mesh carry the same printed hmax).
fn hkey(h: f64) -> u64 {
    h.to_bits()
}

/// The tightest-tolerance row of `backend` at each hmax, sorted by DOFs.
fn tightest<'r>(rows: &'r [SweepRow], backend: &str) -> Vec<&'r SweepRow> {
    let mut best: BTreeMap<u64, &SweepRow> = BTreeMap::new();
    for r in rows.iter().filter(|r| r.backend == backend) {
        best.entry(hkey(r.hmax))
            .and_modify(|b| {
                if r.tol.total_cmp(&b.tol).is_lt() || b.tol.is_nan() {
                    *b = r;
                }
            })
            .or_insert(r);
    }
    let mut v: Vec<&SweepRow> = best.into_values().collect();
    v.sort_by(|a, b| a.dofs.cmp(&b.dofs).then(a.hmax.total_cmp(&b.hmax)));
    v
}

/// Whether a point can be drawn on log–log axes.
fn drawable(p: (f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite() && p.0 > 0.0 && p.1 > 0.0
}

/// `"name (slope 1.08)"`, or just the name when no slope can be fitted.
fn slope_label(name: &str, line: &[(f64, f64)]) -> String {
    match fit_slope(line) {
        Some(s) => format!("{name} (slope {s:.2})"),
        None => name.to_string(),
    }
}

/// One curve per backend over its tightest-tolerance rows, with `y` of each row.
fn per_backend_curves(
    rows: &[SweepRow],
    backends: &[&str],
    y: impl Fn(&SweepRow) -> f64,
) -> Vec<Curve> {
    backends
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let mut curve = Curve::backend(k, String::new());
            for r in tightest(rows, b) {
                let p = (r.dofs as f64, y(r));
                if !drawable(p) {
                    continue;
                }
                if r.solved() {
                    curve.line.push(p);
                } else {
                    curve.hollow.push(p);
                }
            }
            curve.label = slope_label(b, &curve.line);
            curve
        })
        .collect()
}

/// Plot 1: solve time and floor against DOFs.
fn time_vs_dofs(rows: &[SweepRow], backends: &[&str], title: &str) -> Option<Figure> {
    let mut curves = per_backend_curves(rows, backends, |r| r.solve_s);
    // The floor per hmax (the smallest positive value recorded for that mesh).
    let mut floor: BTreeMap<u64, (f64, f64)> = BTreeMap::new();
    for r in rows {
        let p = (r.dofs as f64, r.floor_s);
        if drawable(p) {
            floor
                .entry(hkey(r.hmax))
                .and_modify(|q| q.1 = q.1.min(p.1))
                .or_insert(p);
        }
    }
    let mut line: Vec<(f64, f64)> = floor.into_values().collect();
    line.sort_by(|a, b| a.0.total_cmp(&b.0));
    curves.push(Curve::floor(slope_label("floor", &line), line));
    Some(Figure {
        heading: heading(title, "solve time vs DOFs"),
        x_desc: "DOFs".into(),
        y_desc: "solve time (s)".into(),
        curves,
        hline: None,
        notes: Vec::new(),
    })
}

/// Plot 2: solve time ÷ floor against DOFs.
fn ratio_vs_dofs(rows: &[SweepRow], backends: &[&str], title: &str) -> Option<Figure> {
    let curves = per_backend_curves(rows, backends, |r| {
        if r.ratio_to_floor.is_finite() {
            r.ratio_to_floor
        } else {
            r.solve_s / r.floor_s
        }
    });
    Some(Figure {
        heading: heading(title, "solve time ÷ floor vs DOFs"),
        x_desc: "DOFs".into(),
        y_desc: "solve time / floor time (dimensionless)".into(),
        curves,
        hline: Some((1.0, "floor (ratio 1)".into())),
        notes: Vec::new(),
    })
}

/// Plot 4: iterations against DOFs.
fn iterations_vs_dofs(rows: &[SweepRow], backends: &[&str], title: &str) -> Option<Figure> {
    let curves = per_backend_curves(rows, backends, |r| r.iterations as f64);
    Some(Figure {
        heading: heading(title, "iterations vs DOFs"),
        x_desc: "DOFs".into(),
        y_desc: "iterations (count)".into(),
        curves,
        hline: None,
        notes: Vec::new(),
    })
}

/// Plot 3: error against solve time across tolerances at the finest hmax.
fn work_precision(rows: &[SweepRow], backends: &[&str], title: &str) -> Option<Figure> {
    let finest = rows
        .iter()
        .map(|r| r.hmax)
        .filter(|h| h.is_finite())
        .min_by(f64::total_cmp)?;
    let at: Vec<&SweepRow> = rows
        .iter()
        .filter(|r| hkey(r.hmax) == hkey(finest))
        .collect();
    let mut tols: Vec<f64> = at
        .iter()
        .filter(|r| r.error_vs_reference.is_some_and(f64::is_finite))
        .map(|r| r.tol)
        .filter(|t| t.is_finite())
        .collect();
    tols.sort_by(f64::total_cmp);
    tols.dedup();
    if tols.len() < 2 {
        return None;
    }
    let dofs = at.first().map_or(0, |r| r.dofs);
    let mut clamped = false;
    let curves = backends
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let mut mine: Vec<&&SweepRow> = at.iter().filter(|r| r.backend == *b).collect();
            // Loose to tight tolerance.
            mine.sort_by(|a, b| b.tol.total_cmp(&a.tol));
            // No slope here: error vs time is not a power law (tolerances, not sizes, vary).
            let mut curve = Curve::backend(k, (*b).to_string());
            for r in mine {
                let Some(err) = r.error_vs_reference else {
                    continue;
                };
                let y = if err == 0.0 { ERROR_FLOOR } else { err };
                let p = (r.solve_s, y);
                if !drawable(p) {
                    continue;
                }
                if r.solved() {
                    curve.line.push(p);
                } else {
                    curve.hollow.push(p);
                }
                clamped |= err == 0.0;
            }
            curve
        })
        .collect();
    let mut notes = Vec::new();
    if clamped {
        notes.push(format!("error 0 drawn at {ERROR_FLOOR:e}"));
    }
    Some(Figure {
        heading: heading(
            title,
            &format!("work–precision at hmax = {finest} ({dofs} DOFs)"),
        ),
        x_desc: "solve time (s)".into(),
        y_desc: "error vs reference (max |Δu| / max |u|)".into(),
        curves,
        hline: None,
        notes,
    })
}
