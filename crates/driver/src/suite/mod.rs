//! `signorini suite DIR`: every scene of a directory through every backend, each answer checked
//! against the scene's stored expectation — a solver regression suite.
//!
//! * [`discover`] finds the scenes (`*.toml`, recursively, sorted by path); a case is named by
//!   its path relative to the directory without `.toml`.
//! * [`run_case`] reads a scene and its expectation ([`expectation`]), meshes and assembles it
//!   once, times the floor ([`crate::compare`]'s: one factorisation + solve of A), solves the same
//!   QP with each backend and checks each answer ([`check`]).
//! * [`run()`] does so for every case; [`summary`] condenses the backends' results as qpbenchmark
//!   does; [`bless`] writes expectations from the answers; [`baseline`] compares with an earlier
//!   run's `suite.json`; [`table`], [`junit`] and [`write`](mod@write) present the outcome.
//!
//! Nothing a case does stops the suite: a scene that cannot be read or meshed, or an expectation
//! that cannot be parsed, is that case's error (a regression), and the other cases still run.

use std::path::{Path, PathBuf};
use std::time::Instant;

use signorini_core::mesh::MeshLimits;
use signorini_core::qp::{KktResiduals, SolveOptions};
use signorini_core::report::{RunReport, Timings};
use signorini_core::scene::Scene;
use signorini_core::solve::{self, Solution};

use crate::backends::{make_backend, BackendKind};
use crate::compare::{measure_floor, solve_each};
use crate::run;

pub mod baseline;
pub mod bless;
pub mod changes;
pub mod check;
pub mod expectation;
pub mod junit;
pub mod profile;
pub mod report;
#[cfg(test)]
pub(crate) mod sample;
pub mod summary;
pub mod table;
pub mod write;

use expectation::Expectation;
use report::{CaseReport, CaseRun, Figures, PairForce, ProbeValue, SuiteReport, Verdict};

/// The backends a suite runs when none are named: every method, each in its own form (those
/// not compiled in are left out by the caller, see [`BackendKind::available`]).
pub const DEFAULT_BACKENDS: [BackendKind; 6] = BackendKind::ALL;

/// What every case is run with.
#[derive(Debug, Clone)]
pub struct SuiteSettings {
    /// The backends, in order.
    pub backends: Vec<BackendKind>,
    /// Tolerance, time limit and iteration cap of every solve.
    pub solve: SolveOptions,
    /// Mesh size limits.
    pub limits: MeshLimits,
    /// Solves timed per backend and case (at least 1); the median is reported (see
    /// [`REPEAT_BELOW_S`]).
    pub repeat: usize,
    /// Run only the cases whose name contains one of these texts (empty: every case).
    pub only: Vec<String>,
}

/// Only a solve that succeeded in less than this many seconds is repeated: longer times are not
/// dominated by the timer's and the scheduler's noise, and repeating them would cost much.
pub const REPEAT_BELOW_S: f64 = 1.0;

/// Why a suite could not start.
#[derive(Debug, thiserror::Error)]
pub enum SuiteError {
    /// The directory could not be listed.
    #[error("cannot read the suite directory {}", path.display())]
    Io {
        /// The directory.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The directory holds no scene.
    #[error("{0} holds no scene (*.toml), nor does any directory below it")]
    Empty(PathBuf),
    /// `only` selects no case.
    #[error("no case of {dir} has a name containing {only}; its cases: {cases}")]
    NoneSelected {
        /// The suite directory.
        dir: PathBuf,
        /// The texts asked for, quoted.
        only: String,
        /// The suite's case names.
        cases: String,
    },
}

/// Every `*.toml` file under `dir` (recursively; hidden entries skipped), sorted by path; `dir`
/// itself when it is a scene file (a suite of one).
pub fn discover(dir: &Path) -> Result<Vec<PathBuf>, SuiteError> {
    if dir.is_file() && dir.extension().is_some_and(|e| e == "toml") {
        return Ok(vec![dir.to_path_buf()]);
    }
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), SuiteError> {
        let io = |source| SuiteError::Io {
            path: dir.to_path_buf(),
            source,
        };
        for entry in std::fs::read_dir(dir).map_err(io)? {
            let entry = entry.map_err(io)?;
            let path = entry.path();
            if entry.file_name().to_string_lossy().starts_with('.') {
                continue;
            }
            if path.is_dir() {
                walk(&path, out)?;
            } else if path.extension().is_some_and(|e| e == "toml") {
                out.push(path);
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    walk(dir, &mut out)?;
    if out.is_empty() {
        return Err(SuiteError::Empty(dir.to_path_buf()));
    }
    out.sort();
    Ok(out)
}

/// The case name of `scene` in the suite at `dir`: its relative path with `/` separators and
/// without `.toml` (its file stem when the suite is the scene file itself).
pub fn case_name(dir: &Path, scene: &Path) -> String {
    let rel = match scene.strip_prefix(dir) {
        Ok(rel) if !rel.as_os_str().is_empty() => rel,
        _ => Path::new(scene.file_name().unwrap_or(scene.as_os_str())),
    }
    .with_extension("");
    rel.components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join("/")
}

/// Where a suite run is, for a progress bar.
#[derive(Debug, Clone, Copy)]
pub struct Step<'a> {
    /// The case's index (0-based) and the number of cases.
    pub case: usize,
    /// Number of cases.
    pub cases: usize,
    /// The case's name.
    pub name: &'a str,
    /// What runs now: `mesh` or a backend's name.
    pub what: &'a str,
}

/// Runs every scene under `dir` ([`discover`]); `progress` is told each step.  Summaries are
/// filled in; provenance is left to the caller.
pub fn run(
    dir: &Path,
    settings: &SuiteSettings,
    mut progress: impl FnMut(Step<'_>),
) -> Result<SuiteReport, SuiteError> {
    let all: Vec<(PathBuf, String)> = discover(dir)?
        .into_iter()
        .map(|p| {
            let name = case_name(dir, &p);
            (p, name)
        })
        .collect();
    let scenes: Vec<&(PathBuf, String)> = all
        .iter()
        .filter(|(_, name)| {
            settings.only.is_empty() || settings.only.iter().any(|o| name.contains(o.as_str()))
        })
        .collect();
    if scenes.is_empty() {
        return Err(SuiteError::NoneSelected {
            dir: dir.to_path_buf(),
            only: settings
                .only
                .iter()
                .map(|o| format!("\"{o}\""))
                .collect::<Vec<_>>()
                .join(" or "),
            cases: all
                .iter()
                .map(|(_, n)| n.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        });
    }
    let mut cases = Vec::with_capacity(scenes.len());
    for (i, (path, name)) in scenes.iter().enumerate() {
        cases.push(run_case(path, name, settings, |what| {
            progress(Step {
                case: i,
                cases: scenes.len(),
                name,
                what,
            })
        }));
    }
    let backends: Vec<String> = settings
        .backends
        .iter()
        .map(|k| k.name().to_string())
        .collect();
    let time_limit_s = settings.solve.time_limit.map(|t| t.as_secs_f64());
    let summary = summary::summarise(&backends, &cases, time_limit_s);
    Ok(SuiteReport {
        provenance: None,
        dir: dir.display().to_string(),
        tolerance: settings.solve.tol,
        time_limit_s,
        repeat: settings.repeat,
        backends,
        cases,
        summary,
        baseline: None,
    })
}

/// The SHA-256 of a suite's scenes: of the text holding one line `NAME SHA256` per case, in
/// order (`suite.json`'s `provenance.scene_sha256`): equal for two runs exactly when they ran
/// the same scene files under the same names.
pub fn suite_sha256(cases: &[CaseReport]) -> String {
    let list: String = cases
        .iter()
        .map(|c| format!("{} {}\n", c.name, c.sha256))
        .collect();
    crate::digest::sha256_hex(list.as_bytes())
}

/// Runs one scene (see the module's docs); `progress` is told `mesh`, then each backend.  A
/// case that cannot run has its `error` set and no run.
pub fn run_case(
    path: &Path,
    name: &str,
    settings: &SuiteSettings,
    progress: impl FnMut(&str),
) -> CaseReport {
    let mut case = CaseReport {
        name: name.to_string(),
        scene: path.display().to_string(),
        sha256: String::new(),
        title: String::new(),
        dofs: 0,
        constraints: 0,
        load: f64::NAN,
        floor_s: f64::NAN,
        expectation: None,
        error: None,
        runs: Vec::new(),
    };
    if let Err(error) = fill_case(&mut case, path, settings, progress) {
        case.runs.clear();
        case.error = Some(error);
    }
    case
}

/// [`run_case`]'s work: fills `case` in as it goes; the first failure is returned as the case's
/// error.
fn fill_case(
    case: &mut CaseReport,
    path: &Path,
    settings: &SuiteSettings,
    mut progress: impl FnMut(&str),
) -> Result<(), String> {
    progress("mesh");
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    case.sha256 = crate::digest::sha256_hex(&bytes);
    let scene = Scene::from_path(path).map_err(|e| e.to_string())?;
    case.title = scene.title.clone();
    let expectation_path = expectation::path_for(path);
    let expectation = Expectation::read(&expectation_path).map_err(|e| e.to_string())?;
    if expectation.is_some() {
        case.expectation = Some(expectation_path.display().to_string());
    }
    let start = Instant::now();
    let run::Prepared {
        model,
        qp,
        mesh_s,
        assemble_s,
    } = run::prepare(&scene, &settings.limits).map_err(|e| e.to_string())?;
    let model = &model;
    case.dofs = model.free.len();
    case.constraints = model.rows();
    let load: f64 = model.load.iter().map(|f| f.abs()).sum();
    case.load = load;
    let floor = measure_floor(&qp).map_err(|e| e.to_string())?;
    case.floor_s = floor.seconds;
    let qp = solve::ScaledQp::new(qp);
    let outcomes = if model.rows() == 0 {
        // No contact row: one linear solve ("cholesky"), whichever backend is named.
        progress("cholesky");
        let first = settings
            .backends
            .first()
            .copied()
            .unwrap_or(BackendKind::Clarabel);
        let result = make_backend(first)
            .map_err(|e| e.to_string())
            .and_then(|mut b| {
                solve::solve_scaled(model, &qp, b.as_mut(), &settings.solve)
                    .map_err(|e| e.to_string())
            });
        vec![result.map_err(|e| ("cholesky".to_string(), e))]
    } else {
        let mut o = solve_each(
            model,
            &qp,
            &settings.backends,
            &settings.solve,
            &mut progress,
        )
        .map_err(|e| e.to_string())?;
        repeat_timing(model, &qp, settings, &mut o);
        o
    };
    for (i, outcome) in outcomes.into_iter().enumerate() {
        // Named as asked (`auto` stays `auto`, whichever backend it chose).
        let name = if model.rows() == 0 {
            "cholesky"
        } else {
            settings.backends[i].name()
        };
        let mut run = match outcome {
            Ok(solution) => {
                let timings = Timings {
                    mesh: mesh_s,
                    assemble: assemble_s,
                    solve: solution.solve_time.as_secs_f64(),
                    total: start.elapsed().as_secs_f64(),
                };
                let (solution, _fields, report) =
                    run::finish(&scene, model, solution, settings.solve.tol, timings);
                measured_run(&solution, &report, floor.seconds)
            }
            Err((_, message)) => error_run(name, &message),
        };
        run.backend = name.to_string();
        case.runs.push(run);
    }
    for run in &mut case.runs {
        let (verdict, notes) = check::check(
            expectation.as_ref(),
            check::Answer {
                backend: &run.backend,
                status: &run.status,
                figures: &run.figures,
            },
            load,
        );
        run.verdict = verdict;
        run.notes = notes;
    }
    Ok(())
}

/// Re-runs each backend whose first solve succeeded in less than [`REPEAT_BELOW_S`] until it
/// has `settings.repeat` timings, and reports their median as its solve time (the answer kept
/// is the first one: the backends are deterministic).
fn repeat_timing(
    model: &signorini_core::model::Model,
    qp: &solve::ScaledQp,
    settings: &SuiteSettings,
    outcomes: &mut [crate::compare::BackendOutcome],
) {
    if settings.repeat <= 1 {
        return;
    }
    for (kind, outcome) in settings.backends.iter().zip(outcomes.iter_mut()) {
        let Ok(first) = outcome else { continue };
        if first.status != signorini_core::qp::QpStatus::Solved
            || first.solve_time.as_secs_f64() >= REPEAT_BELOW_S
        {
            continue;
        }
        let mut times = vec![first.solve_time];
        for _ in 1..settings.repeat {
            let Ok(mut backend) = make_backend(*kind) else {
                break;
            };
            match solve::solve_scaled(model, qp, backend.as_mut(), &settings.solve) {
                Ok(again) => times.push(again.solve_time),
                Err(_) => break,
            }
        }
        times.sort();
        first.solve_time = times[times.len() / 2];
    }
}

/// The figures of a report: objective, largest displacement, pair forces, probes.
pub fn figures(report: &RunReport) -> Figures {
    Figures {
        objective: report.objective,
        max_displacement: report
            .bodies
            .iter()
            .map(|b| b.max_displacement)
            .fold(0.0, f64::max),
        contact_forces: report
            .contacts
            .iter()
            .map(|c| PairForce {
                bodies: c.bodies.clone(),
                normal_force: c.normal_force,
                tangential_force: c.tangential_force,
            })
            .collect(),
        probes: report
            .probes
            .iter()
            .map(|p| ProbeValue {
                name: p.name.clone(),
                displacement: p.displacement,
            })
            .collect(),
    }
}

/// A backend's run as measured, before the check.
fn measured_run(solution: &Solution, report: &RunReport, floor_s: f64) -> CaseRun {
    let solve_s = solution.solve_time.as_secs_f64();
    CaseRun {
        backend: solution.backend.clone(),
        status: solution.status.as_str().to_string(),
        backend_status: solution.backend_status.as_str().to_string(),
        iterations: solution.iterations,
        solve_s,
        ratio_to_floor: solve_s / floor_s,
        figures: figures(report),
        residuals: solution.residuals,
        verdict: Verdict::Unchecked,
        notes: Vec::new(),
        message: solution.message.clone(),
    }
}

/// The run of a backend that could not run on the problem: status `error`, nothing measured.
fn error_run(backend: &str, message: &str) -> CaseRun {
    CaseRun {
        backend: backend.to_string(),
        status: "error".to_string(),
        backend_status: "error".to_string(),
        iterations: 0,
        solve_s: f64::NAN,
        ratio_to_floor: f64::NAN,
        figures: Figures {
            objective: f64::NAN,
            max_displacement: f64::NAN,
            contact_forces: Vec::new(),
            probes: Vec::new(),
        },
        residuals: KktResiduals::UNMEASURABLE,
        verdict: Verdict::Unchecked,
        notes: Vec::new(),
        message: Some(message.to_string()),
    }
}
