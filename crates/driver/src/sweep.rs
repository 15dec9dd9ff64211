//! `signorini sweep`: cost and accuracy as the mesh is refined, per backend and tolerance.
//!
//! For each hmax (coarse to fine) the scene is meshed and assembled (`repeat` times, median
//! times), the floor is timed (one unconstrained factor + solve of the same A), then every
//! (tolerance, backend) point is solved `repeat` times.  Tolerances run tightest first so that the
//! reference of a mesh (the solved answer with the smallest residuals at the tightest tolerance)
//! is known before the looser points are measured against it.  Each point is appended to
//! `sweep.csv` as soon as it is done, so an interrupted sweep keeps what finished and `resume`
//! skips it.  At the end the file is rewritten once with `error_vs_finest` filled in: the
//! relative difference to the finest mesh's reference, in max displacement and at every probe.

use std::collections::{HashMap, HashSet};
use std::fs::OpenOptions;
use std::path::{Path, PathBuf};
use std::time::Duration;

use serde::{Deserialize, Serialize};
use signorini_core::mesh::MeshLimits;
use signorini_core::qp::{QpStatus, SolveOptions};
use signorini_core::report::interpolate;
use signorini_core::scene::Scene;
use signorini_core::solve::{self, Solution};

use crate::backends::{make_backend, BackendKind};
use crate::output::{self, OutputError};
use crate::run::{self, RunError};

/// What to sweep.
#[derive(Debug, Clone)]
pub struct SweepPlan {
    /// Mesh sizes (any order; run coarse to fine).
    pub hmax: Vec<f64>,
    /// Bodies whose hmax is swept (empty: all).
    pub bodies: Vec<String>,
    /// Backends.
    pub backends: Vec<BackendKind>,
    /// Tolerances (any order; run tightest first).
    pub tols: Vec<f64>,
    /// Runs per point; medians are reported.
    pub repeat: usize,
    /// Wall-clock limit of one solve; a backend that exceeds it is skipped on finer meshes.
    pub time_limit: Option<Duration>,
    /// Skip points already in the CSV.
    pub resume: bool,
}

/// Why a sweep stopped.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// A run failed.
    #[error(transparent)]
    Run(#[from] RunError),
    /// Reading or writing the CSV failed.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The plan is inconsistent.
    #[error("{0}")]
    Plan(String),
}

/// One row of `sweep.csv`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Point {
    /// Swept hmax.
    pub hmax: f64,
    /// Free DOFs.
    pub dofs: usize,
    /// Contact rows.
    pub constraints: usize,
    /// Backend name.
    pub backend: String,
    /// Requested tolerance.
    pub tol: f64,
    /// Core-checked status.
    pub status: String,
    /// Backend iterations.
    pub iterations: usize,
    /// Median meshing time, s.
    pub mesh_s: f64,
    /// Median assembly time, s.
    pub assemble_s: f64,
    /// Median solve time, s.
    pub solve_s: f64,
    /// Median floor (factor + solve of A), s.
    pub floor_s: f64,
    /// solve_s / floor_s.
    pub ratio_to_floor: f64,
    /// max nodal |u − u_ref| / max |u_ref| against the same mesh's reference.
    pub error_vs_reference: Option<f64>,
    /// Relative difference to the finest mesh (max displacement and probes).
    pub error_vs_finest: Option<f64>,
    /// Largest nodal displacement.
    pub max_displacement: f64,
    /// Peak resident memory while the point was solved (model included), MiB.
    pub peak_rss_mb: f64,
    /// Core residual: penetration (length).
    pub max_penetration: f64,
    /// Core residual: stationarity.
    pub stationarity: f64,
    /// Core residual: complementarity.
    pub complementarity: f64,
    /// Probe displacements `name:ux:uy` joined by `;`.
    pub probes: String,
}

/// Peak resident set size of this process in MiB (Linux `VmHWM`; 0 elsewhere).
pub fn peak_rss_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
        })
        .map(|kb| kb / 1024.0)
        .unwrap_or(0.0)
}

/// Resets the peak RSS counter so the next reading covers one point (Linux ≥ 4.0; best effort).
fn reset_peak_rss() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn max_displacement(u: &[f64]) -> f64 {
    u.chunks(2).map(|p| p[0].hypot(p[1])).fold(0.0, f64::max)
}

fn probes_text(scene: &Scene, model: &signorini_core::model::Model, u: &[f64]) -> String {
    scene
        .probes
        .iter()
        .map(|p| {
            let d = model.body_displacements(p.body, u);
            let v = interpolate(&model.meshes[p.body], &d, p.point, scene.tolerance())
                .unwrap_or([f64::NAN, f64::NAN]);
            format!("{}:{:e}:{:e}", p.name, v[0], v[1])
        })
        .collect::<Vec<_>>()
        .join(";")
}

fn parse_probes(text: &str) -> HashMap<String, [f64; 2]> {
    text.split(';')
        .filter_map(|item| {
            let mut parts = item.split(':');
            let name = parts.next()?.to_string();
            let ux = parts.next()?.parse().ok()?;
            let uy = parts.next()?.parse().ok()?;
            Some((name, [ux, uy]))
        })
        .collect()
}

/// The scene with hmax set for the named bodies (all when `bodies` is empty).
pub fn with_hmax(scene: &Scene, bodies: &[String], hmax: f64) -> Scene {
    let mut s = scene.clone();
    for b in &mut s.bodies {
        if bodies.is_empty() || bodies.contains(&b.name) {
            b.hmax = hmax;
        }
    }
    s
}

/// Reads the points of an existing `sweep.csv`.
pub fn read_points(path: &Path) -> Result<Vec<Point>, OutputError> {
    let mut reader = csv::Reader::from_path(path).map_err(|e| OutputError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e),
    })?;
    reader
        .deserialize()
        .enumerate()
        .map(|(i, r)| {
            r.map_err(|e| OutputError::Mismatch(format!("{}: row {}: {e}", path.display(), i + 2)))
        })
        .collect()
}

fn append(path: &Path, point: &Point, header: bool) -> Result<(), OutputError> {
    let io = |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(io)?;
    let mut w = csv::WriterBuilder::new()
        .has_headers(header)
        .from_writer(file);
    w.serialize(point)
        .map_err(|e| io(std::io::Error::other(e)))?;
    w.flush().map_err(io)
}

fn key(hmax: f64, backend: &str, tol: f64) -> String {
    format!("{hmax:e}|{backend}|{tol:e}")
}

/// Runs the sweep, appending to `dir/sweep.csv`; `progress(done, total, what)` after each point.
/// Returns the CSV path and every point of the file (earlier runs' included when resuming).
pub fn sweep(
    scene: &Scene,
    plan: &SweepPlan,
    options: &SolveOptions,
    limits: &MeshLimits,
    dir: &Path,
    mut progress: impl FnMut(usize, usize, &str),
) -> Result<(PathBuf, Vec<Point>), SweepError> {
    if plan.hmax.is_empty() || plan.backends.is_empty() || plan.tols.is_empty() {
        return Err(SweepError::Plan(
            "a sweep needs at least one hmax, one backend and one tolerance".into(),
        ));
    }
    if let Some(h) = plan.hmax.iter().find(|h| !(h.is_finite() && **h > 0.0)) {
        return Err(SweepError::Plan(format!(
            "--hmax values must be positive, got {h}"
        )));
    }
    if let Some(t) = plan
        .tols
        .iter()
        .find(|t| !(t.is_finite() && **t > 0.0 && **t < 1.0))
    {
        return Err(SweepError::Plan(format!(
            "--tol values must lie in (0, 1), got {t}"
        )));
    }
    for name in &plan.bodies {
        if scene.body_index(name).is_none() {
            return Err(SweepError::Plan(format!(
                "--bodies names an unknown body \"{name}\""
            )));
        }
    }
    std::fs::create_dir_all(dir).map_err(|source| OutputError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let csv_path = dir.join("sweep.csv");
    let mut points = if plan.resume && csv_path.exists() {
        read_points(&csv_path)?
    } else {
        if csv_path.exists() {
            std::fs::remove_file(&csv_path).map_err(|source| OutputError::Io {
                path: csv_path.clone(),
                source,
            })?;
        }
        Vec::new()
    };
    let done: HashSet<String> = points
        .iter()
        .map(|p| key(p.hmax, &p.backend, p.tol))
        .collect();
    let mut hmaxes = plan.hmax.clone();
    hmaxes.sort_by(|a, b| b.total_cmp(a));
    hmaxes.dedup();
    let mut tols = plan.tols.clone();
    tols.sort_by(f64::total_cmp);
    tols.dedup();
    let total = hmaxes.len() * tols.len() * plan.backends.len();
    let mut count = 0;
    let mut given_up: HashSet<BackendKind> = HashSet::new();
    let repeat = plan.repeat.max(1);

    for &h in &hmaxes {
        let todo: Vec<(f64, BackendKind)> = tols
            .iter()
            .flat_map(|&t| plan.backends.iter().map(move |&b| (t, b)))
            .filter(|(t, b)| !done.contains(&key(h, b.name(), *t)))
            .collect();
        if todo.is_empty() {
            count += tols.len() * plan.backends.len();
            progress(count, total, &format!("hmax {h}: already done"));
            continue;
        }
        let s = with_hmax(scene, &plan.bodies, h);
        let mut mesh_times = Vec::with_capacity(repeat);
        let mut assemble_times = Vec::with_capacity(repeat);
        let mut prepared = None;
        for _ in 0..repeat {
            let p = run::prepare(&s, limits).map_err(RunError::from)?;
            mesh_times.push(p.mesh_s);
            assemble_times.push(p.assemble_s);
            prepared = Some(p);
        }
        let Some(mut prepared) = prepared else {
            continue;
        };
        if prepared.model.rows() == 0 {
            return Err(RunError::NoContact(format!("the mesh at hmax {h}")).into());
        }
        let qp = solve::ScaledQp::new(prepared.model.take_qp().map_err(RunError::from)?);
        let model = &prepared.model;
        // One untimed factorisation first: the first touch of a large factor's memory costs page
        // faults that later solves (the backends') do not pay; timing it cold inflated the floor
        // twofold at 10⁶ DOFs.
        solve::floor_time(&qp.problem).map_err(|e| RunError::from(solve::SolveError::from(e)))?;
        let floors: Vec<f64> = (0..repeat)
            .map(|_| solve::floor_time(&qp.problem).map(|d| d.as_secs_f64()))
            .collect::<Result<_, _>>()
            .map_err(|e| RunError::from(solve::SolveError::from(e)))?;
        let (mesh_s, assemble_s, floor_s) =
            (median(mesh_times), median(assemble_times), median(floors));

        let mut reference: Option<(f64, Vec<f64>)> = None; // (residual, displacement)
        for (t, kind) in tols
            .iter()
            .flat_map(|&t| plan.backends.iter().map(move |&b| (t, b)))
        {
            let label = format!("hmax {h} {} tol {t:e}", kind.name());
            let skip_row = done.contains(&key(h, kind.name(), t));
            // The tightest tolerance is always solved (again, if resuming) to fix the reference.
            let needed_for_reference = t == tols[0] && reference.is_none();
            if (skip_row && !needed_for_reference) || given_up.contains(&kind) {
                count += 1;
                progress(count, total, &label);
                continue;
            }
            let mut backend = make_backend(kind).map_err(|e| {
                RunError::from(solve::SolveError::Qp(
                    signorini_core::qp::QpError::Unavailable {
                        backend: kind.name(),
                        reason: e.to_string(),
                    },
                ))
            })?;
            let point_options = SolveOptions {
                tol: t,
                time_limit: plan.time_limit,
                ..options.clone()
            };
            // Peak memory of this point: the model (resident now) plus what the backend adds.
            reset_peak_rss();
            let mut times = Vec::with_capacity(repeat);
            let mut last: Option<Solution> = None;
            for _ in 0..repeat {
                let sol = solve::solve_scaled(model, &qp, backend.as_mut(), &point_options)
                    .map_err(RunError::from)?;
                times.push(sol.solve_time.as_secs_f64());
                let stop = sol.status == QpStatus::TimeLimit;
                last = Some(sol);
                if stop {
                    break;
                }
            }
            let Some(sol) = last else { continue };
            if sol.status == QpStatus::TimeLimit {
                given_up.insert(kind);
            }
            if t == tols[0] && sol.status == QpStatus::Solved {
                let worst = sol.residuals.worst();
                if reference.as_ref().is_none_or(|(r, _)| worst < *r) {
                    reference = Some((worst, sol.displacement.clone()));
                }
            }
            count += 1;
            progress(count, total, &label);
            if skip_row {
                continue;
            }
            let error_vs_reference = reference.as_ref().map(|(_, u_ref)| {
                let scale = max_displacement(u_ref).max(f64::MIN_POSITIVE);
                u_ref
                    .chunks(2)
                    .zip(sol.displacement.chunks(2))
                    .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
                    .fold(0.0, f64::max)
                    / scale
            });
            let solve_s = median(times);
            let point = Point {
                hmax: h,
                dofs: model.free.len(),
                constraints: model.rows(),
                backend: kind.name().to_string(),
                tol: t,
                status: sol.status.as_str().to_string(),
                iterations: sol.iterations,
                mesh_s,
                assemble_s,
                solve_s,
                floor_s,
                ratio_to_floor: solve_s / floor_s,
                error_vs_reference,
                error_vs_finest: None,
                max_displacement: max_displacement(&sol.displacement),
                peak_rss_mb: peak_rss_mb(),
                max_penetration: sol.residuals.max_penetration,
                stationarity: sol.residuals.stationarity,
                complementarity: sol.residuals.complementarity,
                probes: probes_text(&s, model, &sol.displacement),
            };
            append(&csv_path, &point, !csv_path.exists())?;
            points.push(point);
        }
    }
    fill_error_vs_finest(&mut points);
    output::write_atomically(&csv_path, |w| {
        let mut csv = csv::Writer::from_writer(w);
        for p in &points {
            csv.serialize(p).map_err(std::io::Error::other)?;
        }
        csv.flush()
    })?;
    Ok((csv_path, points))
}

/// Fills `error_vs_finest`: for each point, the largest relative difference to the finest mesh's
/// most accurate solved point, over the max displacement and every probe displacement.
pub fn fill_error_vs_finest(points: &mut [Point]) {
    let finest = points
        .iter()
        .filter(|p| p.status == "solved")
        .min_by(|a, b| {
            a.hmax
                .total_cmp(&b.hmax)
                .then(a.tol.total_cmp(&b.tol))
                .then(a.stationarity.total_cmp(&b.stationarity))
        })
        .cloned();
    let Some(finest) = finest else { return };
    let reference_probes = parse_probes(&finest.probes);
    for p in points.iter_mut() {
        let mut err = (p.max_displacement - finest.max_displacement).abs()
            / finest.max_displacement.max(f64::MIN_POSITIVE);
        for (name, u) in parse_probes(&p.probes) {
            if let Some(r) = reference_probes.get(&name) {
                let scale = r[0].hypot(r[1]).max(finest.max_displacement * 1e-3);
                err = err.max((u[0] - r[0]).hypot(u[1] - r[1]) / scale);
            }
        }
        p.error_vs_finest = err.is_finite().then_some(err);
    }
}
