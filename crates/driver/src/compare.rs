//! `signorini compare`: mesh and assemble once, then the same QP through several backends, each
//! timed against the floor (one unconstrained sparse factorisation + solve of the same A, timed
//! in the same run, on the factor path every backend that factors A uses: the project's
//! fill-reducing ordering, LLᵀ in the kernel faer chooses; see [`signorini_core::solve::floor`]) and
//! compared with the most accurate answer.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use serde::Serialize;
use signorini_core::fem::Dofs;
use signorini_core::linalg::SparseCholesky;
use signorini_core::mesh::MeshLimits;
use signorini_core::model::Model;
use signorini_core::qp::{KktResiduals, QpProblem, QpStatus, SolveOptions};
use signorini_core::scene::Scene;
use signorini_core::solve::{self, Solution};

use crate::backends::{make_backend, BackendKind, Form};
use crate::outdir::{DirLock, OutputSet};
use crate::output::OutputError;
use crate::qp_files::{self, QpFileError};
use crate::run::{self, RunError};

mod fclib;
pub use fclib::compare_fclib;

/// One backend's row of the comparison.
#[derive(Debug, Clone, Serialize)]
pub struct CompareRow {
    /// Backend name.
    pub backend: String,
    /// Core-checked status.
    pub status: String,
    /// The backend's own verdict before the core's check.
    pub backend_status: String,
    /// Backend iterations.
    pub iterations: usize,
    /// Solve wall-clock time, seconds.
    pub solve_s: f64,
    /// `solve_s` / `floor_s`.
    pub ratio_to_floor: f64,
    /// ½uᵀAu − fᵀu.
    pub objective: f64,
    /// Largest nodal displacement difference to the reference backend (for `compare --qp`,
    /// which has no nodes: the largest componentwise difference of x).
    pub max_du: f64,
    /// Number of active contact rows.
    pub active: usize,
    /// Core-computed residuals.
    pub residuals: KktResiduals,
    /// The backend's note, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub message: Option<String>,
    /// `compare --fclib`: how far this answer lies from the file's stored `/solution`
    /// (absent without one, and for a scene or QP files).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stored: Option<crate::fclib_import::StoredDifference>,
}

/// `compare.json`.
#[derive(Debug, Clone, Serialize)]
pub struct CompareReport {
    /// What the comparison can be traced to (program version, scene or QP files' SHA-256,
    /// settings, cores); set by the CLI.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub provenance: Option<signorini_core::report::Provenance>,
    /// Scene title; for `compare --qp`, "QP from DIR" (with the exported scene's title when
    /// the directory's README.txt names one).
    pub scene: String,
    /// The directory the QP was read from (`compare --qp`); absent for a scene.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// Free DOFs (for `compare --qp`: n, the unknowns of A).
    pub dofs: usize,
    /// Contact rows.
    pub constraints: usize,
    /// Requested tolerance.
    pub tolerance: f64,
    /// Meshing time, seconds (absent for `compare --qp`: no mesh).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh_s: Option<f64>,
    /// Assembly time, seconds (absent for `compare --qp`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub assemble_s: Option<f64>,
    /// Time to read and check the QP files, seconds (`compare --qp` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub read_s: Option<f64>,
    /// One unconstrained factorisation + solve of A, seconds (median of three).
    pub floor_s: f64,
    /// Fill-reducing ordering of the floor's factor (`amd` or `metis`).
    pub floor_ordering: String,
    /// Nonzeros of the floor's Cholesky factor L (lower triangle, diagonal included).
    pub floor_nnz_l: usize,
    /// ε, in A's units, when the floor factored A + εI instead of A (ε = 1e-8 · maxⱼ Aⱼⱼ): A is singular
    /// (bodies held by contact alone) or its Cholesky broke down by round-off.  Absent when the
    /// floor factored A itself.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub floor_regularised: Option<f64>,
    /// The backend `max_du` is measured against: the solved one with the smallest residuals.
    pub reference: Option<String>,
    /// One row per backend.
    pub backends: Vec<CompareRow>,
}

fn nodal_difference(a: &[f64], b: &[f64]) -> f64 {
    a.chunks(2)
        .zip(b.chunks(2))
        .map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
        .fold(0.0, f64::max)
}

/// Runs every backend in `kinds` on the scene; `progress` is told each backend's name first.
pub fn compare(
    scene: &Scene,
    kinds: &[BackendKind],
    options: &SolveOptions,
    limits: &MeshLimits,
    progress: impl FnMut(&str),
) -> Result<CompareReport, RunError> {
    let prepared = run::prepare(scene, limits)?;
    if prepared.model.rows() == 0 {
        return Err(RunError::NoContact(format!("scene \"{}\"", scene.title)));
    }
    let qp = solve::ScaledQp::new(prepared.qp);
    let model = &prepared.model;
    let force_scale = model.load.iter().map(|f| f.abs()).sum::<f64>();
    let judge = Judge {
        force_scale,
        difference: nodal_difference,
        // solve's own verdict, derived numbers (stresses, reactions) included.
        check: &|s| run::checked(scene, model, s, options.tol),
        stored: None,
    };
    let runs = run_backends(model, &qp, kinds, options, &judge, progress)?;
    Ok(CompareReport {
        provenance: None,
        scene: scene.title.clone(),
        source: None,
        dofs: model.free.len(),
        constraints: model.rows(),
        tolerance: options.tol,
        mesh_s: Some(prepared.mesh_s),
        assemble_s: Some(prepared.assemble_s),
        read_s: None,
        floor_s: runs.floor_s,
        floor_ordering: runs.floor_ordering,
        floor_nnz_l: runs.floor_nnz_l,
        floor_regularised: runs.floor_regularised,
        reference: runs.reference,
        backends: runs.backends,
    })
}

/// What [`run_backends`] measured.
struct Runs {
    floor_s: f64,
    floor_ordering: String,
    floor_nnz_l: usize,
    floor_regularised: Option<f64>,
    reference: Option<String>,
    backends: Vec<CompareRow>,
}

/// How [`run_backends`] judges and measures the answers.
struct Judge<'a> {
    /// Active rows are counted against this force (see [`signorini_core::report::is_active`]).
    force_scale: f64,
    /// A row's `max_du` to the reference answer.
    difference: fn(&[f64], &[f64]) -> f64,
    /// The verdict `solve` would give the answer ([`run::checked`] for a scene; the core's own,
    /// already applied, for a QP from files, which has no derived numbers).
    check: &'a dyn Fn(Solution) -> Solution,
    /// `compare --fclib` with a stored solution: how far an answer lies from it.
    stored: Option<&'a dyn Fn(&Solution) -> crate::fclib_import::StoredDifference>,
}

/// The floor, then every backend of `kinds` on `qp`, each answer checked by `judge.check`, each
/// row's `max_du` by `judge.difference` against the solved backend with the smallest residuals.
fn run_backends(
    model: &Model,
    qp: &solve::ScaledQp,
    kinds: &[BackendKind],
    options: &SolveOptions,
    judge: &Judge<'_>,
    mut progress: impl FnMut(&str),
) -> Result<Runs, RunError> {
    let floor = measure_floor(&qp.problem)?;
    let floor_s = floor.seconds;
    let outcomes: Vec<BackendOutcome> = solve_each(model, qp, kinds, options, &mut progress)?
        .into_iter()
        .map(|o| o.map(judge.check))
        .collect();
    let solutions: Vec<&Solution> = outcomes.iter().filter_map(|o| o.as_ref().ok()).collect();
    let reference = solutions
        .iter()
        .enumerate()
        .filter(|(_, s)| s.status == QpStatus::Solved)
        .min_by(|(_, a), (_, b)| a.residuals.worst().total_cmp(&b.residuals.worst()))
        .map(|(i, _)| i);
    let backends = outcomes
        .iter()
        .map(|o| {
            let s = match o {
                Ok(s) => s,
                Err((backend, message)) => return error_row(backend, message),
            };
            let largest = s
                .multipliers
                .iter()
                .copied()
                .fold(judge.force_scale, f64::max);
            CompareRow {
                backend: s.backend.clone(),
                status: s.status.as_str().to_string(),
                backend_status: s.backend_status.as_str().to_string(),
                iterations: s.iterations,
                solve_s: s.solve_time.as_secs_f64(),
                ratio_to_floor: s.solve_time.as_secs_f64() / floor_s,
                objective: s.objective,
                max_du: reference
                    .map(|r| (judge.difference)(&s.displacement, &solutions[r].displacement))
                    .unwrap_or(f64::NAN),
                active: s
                    .multipliers
                    .iter()
                    .filter(|l| signorini_core::report::is_active(**l, largest))
                    .count(),
                residuals: s.residuals,
                message: s.message.clone(),
                stored: judge.stored.map(|f| f(s)),
            }
        })
        .collect();
    Ok(Runs {
        floor_s,
        floor_ordering: floor.ordering,
        floor_nnz_l: floor.nnz_l,
        // ε of the scaled Â = A / k̄, brought back to A's units.
        floor_regularised: floor.shift.map(|eps| eps * qp.scaling.stiffness),
        reference: reference.map(|r| solutions[r].backend.clone()),
        backends,
    })
}

/// The floor of a QP: one unconstrained factorisation + solve of its A, timed.
#[derive(Debug, Clone)]
pub(crate) struct Floor {
    /// Median of three timed runs (after one warm-up), seconds.
    pub seconds: f64,
    /// Fill-reducing ordering of the factor (`amd` or `metis`).
    pub ordering: String,
    /// Nonzeros of the factor L.
    pub nnz_l: usize,
    /// ε when A + εI was factored instead of A (see [`solve::Floor::shift`]).
    pub shift: Option<f64>,
}

/// Times the floor of `qp`: a warm-up first (page faults of the first large allocation), then
/// the median of three.
pub(crate) fn measure_floor(qp: &QpProblem) -> Result<Floor, RunError> {
    let floor = solve::floor(qp).map_err(solve::SolveError::from)?;
    let mut floors: Vec<Duration> = (0..3)
        .map(|_| solve::floor_time(qp))
        .collect::<Result<_, _>>()
        .map_err(solve::SolveError::from)?;
    floors.sort();
    Ok(Floor {
        seconds: floors[1].as_secs_f64(),
        ordering: floor.info.ordering.as_str().to_string(),
        nnz_l: floor.info.nnz_l,
        shift: floor.shift,
    })
}

/// What one backend of [`solve_each`] ended with: its solution, or — when it could not run on
/// the problem at all — its name and the reason.
pub(crate) type BackendOutcome = Result<Solution, (String, String)>;

/// Every backend of `kinds` on `qp`, in order; `progress` is told each backend's name first.
/// A backend that cannot run on this problem (the dual form on a floating body, a dense matrix
/// that does not fit) ends as `Err((name, reason))`; the others still run.  Only a failure that
/// is not the backend's (the model's) stops the whole loop.
pub(crate) fn solve_each(
    model: &Model,
    qp: &solve::ScaledQp,
    kinds: &[BackendKind],
    options: &SolveOptions,
    mut progress: impl FnMut(&str),
) -> Result<Vec<BackendOutcome>, RunError> {
    let mut outcomes: Vec<BackendOutcome> = Vec::with_capacity(kinds.len());
    for &kind in kinds {
        progress(kind.name());
        let mut backend = make_backend(kind).map_err(|e| {
            RunError::Solve(solve::SolveError::Qp(
                signorini_core::qp::QpError::Unavailable {
                    backend: kind.name(),
                    reason: e.to_string(),
                },
            ))
        })?;
        match solve::solve_scaled(model, qp, backend.as_mut(), options) {
            Ok(solution) => outcomes.push(Ok(solution)),
            Err(solve::SolveError::Qp(e)) => {
                outcomes.push(Err((kind.name().to_string(), e.to_string())))
            }
            Err(e) => return Err(e.into()),
        }
    }
    Ok(outcomes)
}

/// Largest componentwise difference max_i |a_i − b_i| (NaN when either holds a NaN): a QP read
/// from files has no nodes to pair its unknowns into.
fn componentwise_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, |m: f64, d| {
            if d.is_nan() || m.is_nan() {
                f64::NAN
            } else {
                m.max(d)
            }
        })
}

/// A model whose unknowns are the QP's own (all free, none prescribed, no mesh): what the
/// solve needs to hand back x for a QP that came from files rather than from a scene.
fn bare_model(qp: &QpProblem) -> Model {
    let n = qp.dofs();
    Model {
        meshes: Vec::new(),
        materials: Vec::new(),
        // Two DOFs per node: ⌈n/2⌉ nodes (only the length of an unanswered solve's NaN vector).
        dofs: Dofs::new(&[n.div_ceil(2)]),
        supports: sprs::CsMat::zero((n, 0)),
        fixed_dofs: Vec::new(),
        load: Vec::new(),
        fixed: vec![None; n],
        free: (0..n).collect(),
        contacts: Vec::new(),
        constraints: sprs::CsMat::zero((0, n)),
        gap: Vec::new(),
        tangential: Vec::new(),
        path: None,
        floating: Vec::new(),
        kernel: Vec::new(),
        effects: Vec::new(),
        warnings: Vec::new(),
    }
}

/// Why `compare --qp` stopped before any backend ran.
#[derive(Debug, thiserror::Error)]
pub enum QpCompareError {
    /// The files were refused (bad input: exit code 1).
    #[error(transparent)]
    Files(#[from] QpFileError),
    /// The QP has no constraint row: nothing for the backends to compete on.
    #[error("{0}: B has no row, so the QP is one linear solve and no QP backend runs: nothing to compare")]
    NoRows(String),
    /// The FCLIB file was refused (exit code 1).
    #[error(transparent)]
    Fclib(#[from] crate::fclib::FclibError),
    /// The factor of A would not fit in memory (exit code 3).
    #[error(transparent)]
    Preflight(#[from] signorini_core::preflight::PreflightError),
    /// The floor could not be measured.
    #[error(transparent)]
    Run(#[from] RunError),
}

/// `compare --qp DIR`: reads A, f, B, g (see [`crate::qp_files`]) and runs every backend of
/// `kinds` on them exactly as [`compare`] does on a scene's QP: the same floor, scaling, residual
/// check and rows.  There is no mesh: `mesh_s` and `assemble_s` are absent, `read_s` is the time
/// to read and check the files, `source` the directory, and `max_du` is the largest
/// componentwise difference of x to the reference backend's.  On a QP whose A is singular (a
/// body held by contact alone) the backends that need its null space (the `dual-*` ones, the
/// condensed forms) take it from `N.mtx`; without that file they end in an `error` row with
/// their reason.
pub fn compare_qp(
    dir: &Path,
    kinds: &[BackendKind],
    options: &SolveOptions,
    progress: impl FnMut(&str),
) -> Result<CompareReport, QpCompareError> {
    let start = Instant::now();
    let files = qp_files::read_qp_dir(dir)?;
    let read_s = start.elapsed().as_secs_f64();
    if files.qp.rows() == 0 {
        return Err(QpCompareError::NoRows(dir.display().to_string()));
    }
    if let Some(budget) = signorini_core::memory::available_bytes() {
        signorini_core::preflight::check_factor_memory(&files.qp, budget)?;
    }
    let model = bare_model(&files.qp);
    let force_scale = files.qp.load.iter().map(|f| f.abs()).sum::<f64>();
    let (dofs, constraints) = (files.qp.dofs(), files.qp.rows());
    let qp = solve::ScaledQp::new(files.qp);
    let judge = Judge {
        force_scale,
        difference: componentwise_difference,
        check: &std::convert::identity,
        stored: None,
    };
    let mut runs = run_backends(&model, &qp, kinds, options, &judge, progress)?;
    // A dual-form backend needs A⁻¹, or A's null space when A is singular (a body held by
    // contact alone); a scene's assembly knows the rigid-body modes, the files do not.  When
    // such a backend did not solve and A's Cholesky breaks down, its numbers (x = 0, λ = 0) say
    // nothing: the row becomes an error with the reason.
    let failed_dual = |k: &BackendKind, r: &CompareRow| {
        k.form() == Form::Dual && r.status != "solved" && r.status != "error"
    };
    if qp.problem.kernel.is_empty()
        && kinds
            .iter()
            .zip(&runs.backends)
            .any(|(k, r)| failed_dual(k, r))
        && SparseCholesky::factor(&qp.problem.stiffness).is_err()
    {
        for (k, row) in kinds.iter().zip(runs.backends.iter_mut()) {
            if failed_dual(k, row) {
                let said = row.message.as_deref().unwrap_or("no message");
                *row = error_row(
                    &row.backend,
                    &format!(
                        "A is singular and the QP files carry no null space (N.mtx), which the dual form needs (a body held by contact alone; the primal backends handle it): {said}"
                    ),
                );
            }
        }
    }
    let source = files.dir.display().to_string();
    let scene = match &files.title {
        Some(title) => format!("QP from {source} (exported from \"{title}\")"),
        None => format!("QP from {source}"),
    };
    Ok(file_report(
        scene,
        source,
        (dofs, constraints),
        options.tol,
        read_s,
        runs,
    ))
}

/// The report of a comparison on a problem read from files (no mesh, no assembly).
fn file_report(
    scene: String,
    source: String,
    (dofs, constraints): (usize, usize),
    tolerance: f64,
    read_s: f64,
    runs: Runs,
) -> CompareReport {
    CompareReport {
        provenance: None,
        scene,
        source: Some(source),
        dofs,
        constraints,
        tolerance,
        mesh_s: None,
        assemble_s: None,
        read_s: Some(read_s),
        floor_s: runs.floor_s,
        floor_ordering: runs.floor_ordering,
        floor_nnz_l: runs.floor_nnz_l,
        floor_regularised: runs.floor_regularised,
        reference: runs.reference,
        backends: runs.backends,
    }
}

/// The comparison as a fixed-width text table.
pub fn table(report: &CompareReport) -> String {
    let (unknowns, rows, du) = if report.source.is_some() {
        ("unknowns", "constraint rows", "max|Δx|")
    } else {
        ("DOFs", "contact rows", "max|Δu|")
    };
    let matrix = if report.floor_regularised.is_some() {
        "A + εI*"
    } else {
        "A"
    };
    let mut t = format!(
        "{}\n  {} {unknowns}, {} {rows}; floor (factor + solve of {matrix}, {} ordering, nnz(L) {}) {:.3} ms; reference: {}\n",
        report.scene,
        report.dofs,
        report.constraints,
        report.floor_ordering,
        report.floor_nnz_l,
        report.floor_s * 1e3,
        report.reference.as_deref().unwrap_or("none solved")
    );
    t.push_str(&format!(
        "  {:<11} {:<17} {:>6} {:>10} {:>8} {:>13} {:>9} {:>6} {:>9} {:>9} {:>9} {:>9}\n",
        "backend",
        "status",
        "iter",
        "solve ms",
        "÷floor",
        "objective",
        du,
        "active",
        "penetr.",
        "station.",
        "compl.",
        "min λ"
    ));
    for r in &report.backends {
        if r.status == "error" {
            let message = r.message.as_deref().unwrap_or("");
            t.push_str(&format!("  {:<11} error: {message}\n", r.backend));
            continue;
        }
        t.push_str(&format!(
            "  {:<11} {:<17} {:>6} {:>10.3} {:>8.2} {:>13.6e} {:>9.1e} {:>6} {:>9.1e} {:>9.1e} {:>9.1e} {:>9.1e}\n",
            r.backend,
            r.status,
            r.iterations,
            r.solve_s * 1e3,
            r.ratio_to_floor,
            r.objective,
            r.max_du,
            r.active,
            r.residuals.max_penetration,
            r.residuals.stationarity,
            r.residuals.complementarity,
            r.residuals.min_multiplier
        ));
    }
    for r in &report.backends {
        if let Some(d) = r.stored {
            t.push_str(&format!(
                "  {:<11} against the file's /solution: max|Δv|/max|v| {:.1e}, max|Δr|/max|r| {:.1e}\n",
                r.backend, d.v, d.r
            ));
        }
    }
    if let Some(eps) = report.floor_regularised {
        t.push_str(&format!(
            "  * the floor factored A + εI, ε = {eps:.3e} (1e-8 · max Aⱼⱼ): A itself is singular (a body held by contact alone) or its Cholesky broke down; same pattern and work\n"
        ));
    }
    t
}

/// Writes `compare.json` and `compare.csv` into `dir` (created if missing) as one output set
/// (see [`crate::outdir`]): under the directory's lock, moved into place together with
/// `compare.json` last; on failure the previous files stay as they were.  Returns the paths
/// written, `compare.json` first.
pub fn write(dir: &Path, report: &CompareReport) -> Result<Vec<PathBuf>, OutputError> {
    let lock = DirLock::acquire(dir)?;
    let mut set = OutputSet::new(
        &lock,
        Some("compare.json"),
        &["compare.json", "compare.csv"],
    )?;
    set.write("compare.json", |w| {
        serde_json::to_writer_pretty(&mut *w, report).map_err(std::io::Error::other)?;
        writeln!(w)
    })?;
    set.write("compare.csv", |w| {
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record([
            "backend",
            "status",
            "iterations",
            "solve_s",
            "floor_s",
            "ratio_to_floor",
            "objective",
            "max_du",
            "active",
            "max_penetration",
            "stationarity",
            "complementarity",
            "min_multiplier",
            "dofs",
            "constraints",
        ])?;
        for r in &report.backends {
            csv.write_record([
                r.backend.clone(),
                r.status.clone(),
                r.iterations.to_string(),
                format!("{:e}", r.solve_s),
                format!("{:e}", report.floor_s),
                format!("{:e}", r.ratio_to_floor),
                format!("{:e}", r.objective),
                format!("{:e}", r.max_du),
                r.active.to_string(),
                format!("{:e}", r.residuals.max_penetration),
                format!("{:e}", r.residuals.stationarity),
                format!("{:e}", r.residuals.complementarity),
                format!("{:e}", r.residuals.min_multiplier),
                report.dofs.to_string(),
                report.constraints.to_string(),
            ])?;
        }
        csv.flush()
    })?;
    set.commit()
}

/// The row of a backend that could not run: status `"error"`, the error as its message, every
/// number unmeasured (NaN, written as null in JSON).
fn error_row(backend: &str, message: &str) -> CompareRow {
    CompareRow {
        backend: backend.to_string(),
        status: "error".to_string(),
        backend_status: "error".to_string(),
        iterations: 0,
        solve_s: f64::NAN,
        ratio_to_floor: f64::NAN,
        objective: f64::NAN,
        max_du: f64::NAN,
        active: 0,
        residuals: signorini_core::qp::KktResiduals::UNMEASURABLE,
        message: Some(message.to_string()),
        stored: None,
    }
}
