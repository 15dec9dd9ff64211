//! The steps of a run, each a function with one job: read the scene, mesh, assemble, solve,
//! report, write.

use std::path::{Path, PathBuf};
use std::time::Instant;

use signorini_core::contact;
use signorini_core::memory;
use signorini_core::mesh::MeshLimits;
use signorini_core::model::{self, Model, ModelError};
use signorini_core::preflight::{check_factor_memory, preflight, PreflightError};
use signorini_core::qp::{QpBackend, QpProblem, QpStatus, SolveOptions};
use signorini_core::report::{self, BodyFields, RunReport, Timings};
use signorini_core::scene::{Scene, SceneError};
use signorini_core::solve::{self, Solution, SolveError};

use crate::backends::BackendKind;
use crate::guard;
use crate::outdir::{DirLock, OutputSet};
use crate::output::{self, BodyField, OutputError, VtuFormat};

/// The scene run when none is given: the seed's Experiment 2b.
pub const DEFAULT_SCENE: &str = include_str!("../../../fixtures/seed/exp2b.toml");

/// Anything that stops a run.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The scene is unreadable or invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The scene would need more elements (and memory) than allowed.
    #[error(transparent)]
    Preflight(#[from] PreflightError),
    /// Meshing or assembly refused the scene.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The solve could not run.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// Writing a file failed.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// Backends were asked to compete on a problem without contact rows, where none runs.
    #[error("{0} has no contact constraint row, so it is one linear solve and no QP backend runs: nothing to compare (add a [[contact]] pair, or check its region)")]
    NoContact(String),
}

/// Reads the scene at `path`, or the embedded default when `None`.
pub fn load_scene(path: Option<&Path>) -> Result<Scene, SceneError> {
    match path {
        Some(p) => Scene::from_path(p),
        None => Scene::from_toml(DEFAULT_SCENE),
    }
}

/// A meshed and assembled scene with the time each step took.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// The model (what the report and the output files need).
    pub model: Model,
    /// The reduced QP (what a solve needs).
    pub qp: QpProblem,
    /// Seconds spent meshing.
    pub mesh_s: f64,
    /// Seconds spent assembling.
    pub assemble_s: f64,
}

/// Estimates the cost (refusing a scene whose total element count exceeds the limit), then
/// meshes and assembles, then checks the memory of the factor of A against the machine's
/// available memory ([`prepare_with_budget`] with [`memory::available_bytes`]).  Every command
/// goes through here, `check` included, so they agree.
pub fn prepare(scene: &Scene, limits: &MeshLimits) -> Result<Prepared, RunError> {
    prepare_with_budget(scene, limits, memory::available_bytes())
}

/// [`prepare`] with a memory budget in bytes (`None`: no memory check).  After assembly and
/// before any numeric factorisation, A is ordered and analysed symbolically and the run's peak
/// ([`signorini_core::memory::FactorEstimate`]: factor, its scratch, A, B, vectors) is compared
/// with `budget`; a run that would not fit is refused with
/// [`PreflightError::FactorTooLarge`] (exit 3).  No size is exempt from the check.
pub fn prepare_with_budget(
    scene: &Scene,
    limits: &MeshLimits,
    budget: Option<u64>,
) -> Result<Prepared, RunError> {
    let t0 = Instant::now();
    preflight(scene, limits)?;
    let meshes = model::mesh_scene(scene, limits)?;
    let mesh_s = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let model::Assembly { model, qp } = model::assemble(scene, meshes)?;
    let assemble_s = t1.elapsed().as_secs_f64();
    if let Some(budget) = budget {
        check_factor_memory(&qp, budget)?;
    }
    Ok(Prepared {
        model,
        qp,
        mesh_s,
        assemble_s,
    })
}

/// Everything a solve produced.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The model solved.
    pub model: Model,
    /// The raw solution.
    pub solution: Solution,
    /// Per-body output fields.
    pub fields: Vec<BodyFields>,
    /// The report (`result.json`).
    pub report: RunReport,
}

/// How [`solve_scene_priced`] prices the run's memory before the backend runs ([`guard`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Priced {
    /// By the registry's estimate of this backend (what `check` prints for it).
    Kind(BackendKind),
    /// `auto` with a chain given by name (`--chain`): the walk over it ([`guard::walk`]).
    Chain(Vec<BackendKind>),
    /// The solve path's part only: a backend the registry does not know (a test's, one with
    /// settings of its own), which guards its own allocations.
    PathOnly,
}

impl Priced {
    /// By the backend's name: a name of the registry is priced as that backend, any other as
    /// [`Priced::PathOnly`].
    pub fn by_name(name: &str) -> Self {
        name.parse::<BackendKind>()
            .map_or(Priced::PathOnly, Priced::Kind)
    }
}

/// Meshes, assembles and solves a scene with one backend, its memory priced by its name
/// ([`solve_scene_priced`] with [`Priced::by_name`]).
pub fn solve_scene(
    scene: &Scene,
    backend: &mut dyn QpBackend,
    options: &SolveOptions,
    limits: &MeshLimits,
) -> Result<Outcome, RunError> {
    let priced = Priced::by_name(backend.name());
    solve_scene_priced(scene, backend, priced, options, limits)
}

/// Meshes, assembles and solves a scene with one backend.  Before the solve, the run's peak
/// (the solve path's copies and the backend's own part, [`guard`]) is compared with the memory
/// available: a run that does not fit is refused with `QpError::TooLarge` (exit 3), the figure
/// `check` prints; one that fits runs with the solve path's part held for the backend's own
/// checks ([`signorini_core::memory::hold`]).
pub fn solve_scene_priced(
    scene: &Scene,
    backend: &mut dyn QpBackend,
    priced: Priced,
    options: &SolveOptions,
    limits: &MeshLimits,
) -> Result<Outcome, RunError> {
    let start = Instant::now();
    let prepared = prepare(scene, limits)?;
    let _held = if prepared.qp.rows() == 0 {
        // One sparse Cholesky solve, which `prepare` priced (the factor of A).
        None
    } else {
        let shape = guard::RunShape::of(&prepared.model, &prepared.qp).map_err(SolveError::from)?;
        Some(match priced {
            Priced::Kind(kind) => guard::guard_run(kind, &shape).map_err(SolveError::from)?,
            Priced::Chain(kinds) => {
                let chain = crate::backends::auto::given_chain(&kinds);
                let own = guard::walk(&shape, &chain).map_err(SolveError::from)?;
                let need = guard::BackendNeed {
                    backend: "auto",
                    bytes: shape.path.bytes + own.bytes,
                    path: shape.path.bytes,
                    own: own.bytes,
                    what: own.what,
                };
                guard::refuse_unless_fits(&need, &shape).map_err(SolveError::from)?;
                memory::hold(need.path)
            }
            Priced::PathOnly => memory::hold(shape.path.bytes),
        })
    };
    let qp = solve::ScaledQp::new(prepared.qp);
    let solution = solve::solve_scaled(&prepared.model, &qp, backend, options)?;
    drop(qp);
    let fields = report::body_fields(&prepared.model, &solution);
    let timings = Timings {
        mesh: prepared.mesh_s,
        assemble: prepared.assemble_s,
        solve: solution.solve_time.as_secs_f64(),
        // Everything since the element estimate, the output fields included (docs/scene.md).
        total: start.elapsed().as_secs_f64(),
    };
    let (solution, report) = finish_with_fields(
        scene,
        &prepared.model,
        solution,
        &fields,
        options.tol,
        timings,
    );
    Ok(Outcome {
        model: prepared.model,
        solution,
        fields,
        report,
    })
}

/// The report of a solution and its output fields, with `solved`'s promise kept: a solution the
/// core's check passed whose derived numbers (stresses, reactions: computed after the solve, they
/// may still overflow, E = 1e300 times a finite strain) are not all finite becomes
/// `numerical_error`, the offending figure named in its message.
pub fn finish(
    scene: &Scene,
    model: &Model,
    solution: Solution,
    tol: f64,
    timings: Timings,
) -> (Solution, Vec<BodyFields>, RunReport) {
    let fields = report::body_fields(model, &solution);
    let (solution, report) = finish_with_fields(scene, model, solution, &fields, tol, timings);
    (solution, fields, report)
}

/// The status `solve` gives `solution`: [`finish`]'s, the report and the fields dropped.  What
/// `compare` judges each backend's answer by, so that compare says `solved` exactly when solve
/// does (the timings are not part of the verdict: zeros stand in for them).
pub fn checked(scene: &Scene, model: &Model, solution: Solution, tol: f64) -> Solution {
    finish(scene, model, solution, tol, Timings::default()).0
}

/// [`finish`] with the output fields already computed (so that the caller can time them).
pub fn finish_with_fields(
    scene: &Scene,
    model: &Model,
    mut solution: Solution,
    fields: &[BodyFields],
    tol: f64,
    timings: Timings,
) -> (Solution, RunReport) {
    let mut report = report::run_report(scene, model, &solution, fields, tol, timings);
    if solution.status == QpStatus::Solved {
        if let Some(path) = first_non_finite(&report, fields) {
            let note = format!("{path} is not finite in the scene's units");
            demote(&mut solution, &mut report, QpStatus::NumericalError, note);
        }
    }
    if solution.status == QpStatus::Solved {
        let (note, unjudged) = deformed_verdict(scene, model, fields);
        report
            .warnings
            .extend(unjudged.into_iter().map(|w| report::WarningReport {
                message: w.to_string(),
                warning: w,
            }));
        if let Some(note) = note {
            demote(&mut solution, &mut report, QpStatus::DeformedOverlap, note);
        }
    }
    (solution, report)
}

/// Gives `solution` and its `report` the status `to`, `note` heading the message (the
/// backend's own message kept after it).
fn demote(solution: &mut Solution, report: &mut RunReport, to: QpStatus, note: String) {
    solution.status = to;
    solution.message = Some(match solution.message.take() {
        Some(m) => format!("{note}; backend: {m}"),
        None => note,
    });
    report.status = to.as_str().to_string();
    report.message = solution.message.clone();
}

/// The deformed-geometry check of a solved answer ([`contact::deformed_overlap`]): the deepest
/// slave node inside its deformed master beyond the small-displacement model's allowance,
/// described, or `None` when every slave node keeps out.
pub fn deformed_overlap_note(
    scene: &Scene,
    model: &Model,
    fields: &[BodyFields],
) -> Option<String> {
    deformed_verdict(scene, model, fields).0
}

/// The deformed-geometry check's note ([`deformed_overlap_note`]) and a
/// [`model::ModelWarning::DeformedUnjudged`] for each pair it could not judge (an overlap in a
/// pair that moves more than a tenth of its smaller body).
pub fn deformed_verdict(
    scene: &Scene,
    model: &Model,
    fields: &[BodyFields],
) -> (Option<String>, Vec<model::ModelWarning>) {
    let displacement: Vec<&[[f64; 2]]> = fields.iter().map(|f| f.displacement.as_slice()).collect();
    let check = contact::deformed_check(&model.meshes, &model.contacts, &displacement);
    let name = |b: usize| scene.bodies.get(b).map_or("?", |body| body.name.as_str());
    let unjudged = check
        .unjudged
        .iter()
        .map(|u| model::ModelWarning::DeformedUnjudged {
            pair: u.overlap.pair + 1,
            slave: name(u.overlap.slave).to_string(),
            master: name(u.overlap.master).to_string(),
            position: u.overlap.position,
            depth: u.overlap.depth,
            motion: u.overlap.motion,
            size: u.size,
        })
        .collect();
    let Some(o) = check.worst else {
        return (None, unjudged);
    };
    let why = if o.has_row {
        "its row holds, but it slid past its master segment"
    } else {
        "it has no contact row (outside the region box, or beyond the master's end)"
    };
    let note = format!(
        "contact #{}: slave \"{}\" node at {:?} ends {:.3e} inside master \"{}\" in the deformed \
         configuration ({:.1e} of the pair's motion {:.3e}; the small-displacement model allows \
         {:.1e}): {why}",
        o.pair + 1,
        name(o.slave),
        o.position,
        o.depth,
        name(o.master),
        o.depth / o.motion,
        o.motion,
        o.allowed,
    );
    (Some(note), unjudged)
}

/// The first number of the report (as a JSON path) or of the output fields that is NaN or
/// infinite, if any.
pub fn first_non_finite(report: &RunReport, fields: &[BodyFields]) -> Option<String> {
    fn walk(v: &serde_json::Value, path: &mut String) -> bool {
        match v {
            // serde_json writes NaN and ±inf as null; the report has no other nulls.
            serde_json::Value::Null => true,
            serde_json::Value::Array(items) => items.iter().enumerate().any(|(i, x)| {
                let len = path.len();
                path.push_str(&format!("[{i}]"));
                let found = walk(x, path);
                if !found {
                    path.truncate(len);
                }
                found
            }),
            serde_json::Value::Object(map) => map.iter().any(|(k, x)| {
                let len = path.len();
                path.push('.');
                path.push_str(k);
                let found = walk(x, path);
                if !found {
                    path.truncate(len);
                }
                found
            }),
            _ => false,
        }
    }
    let mut path = String::from("result");
    match serde_json::to_value(report) {
        Ok(v) if walk(&v, &mut path) => return Some(path),
        Ok(_) => {}
        Err(_) => return Some("result".to_string()),
    }
    for (b, f) in fields.iter().enumerate() {
        let bad = |v: &[f64]| v.iter().any(|x| !x.is_finite());
        if bad(f.displacement.as_flattened())
            || bad(f.stress.as_flattened())
            || bad(&f.von_mises)
            || bad(&f.contact_pressure)
        {
            return Some(format!("a field of body {}", report.bodies[b].name));
        }
    }
    None
}

/// The files of a solve, `result.json` (the primary, moved into place last) first;
/// `pressure.svg` only when the model has contact rows.
pub const SOLVE_FILES: [&str; 4] = [
    "result.json",
    "solution.vtu",
    "deformed.svg",
    "pressure.svg",
];

/// Writes `result.json`, `solution.vtu`, `deformed.svg` and — when the model has at least one
/// contact row — `pressure.svg` ([`output::pressure`]) into `dir` (created if missing) as one
/// output set (see [`crate::outdir`]): under the directory's lock (a concurrent run into the
/// same directory is refused with [`OutputError::Locked`]), staged beside the targets and moved
/// into place together, `result.json` last.  A `pressure.svg` of an earlier run is removed when
/// this one has no contact row.  If anything fails, the directory keeps its previous files
/// unchanged and no temporary file is left.  Returns the paths written, in the order above.
pub fn write_outputs(
    dir: &Path,
    scene: &Scene,
    outcome: &Outcome,
) -> Result<Vec<PathBuf>, OutputError> {
    write_outputs_with(dir, scene, outcome, VtuFormat::default())
}

/// [`write_outputs`] with `solution.vtu` in `vtu` ([`VtuFormat::Binary`] there;
/// `signorini solve --vtu`).
pub fn write_outputs_with(
    dir: &Path,
    scene: &Scene,
    outcome: &Outcome,
    vtu: VtuFormat,
) -> Result<Vec<PathBuf>, OutputError> {
    let bodies = BodyField::of_bodies(&outcome.model.meshes, &outcome.fields, &scene.bodies);
    let lock = DirLock::acquire(dir)?;
    let mut set = OutputSet::new(&lock, Some(SOLVE_FILES[0]), &SOLVE_FILES)?;
    set.write(SOLVE_FILES[0], |w| {
        serde_json::to_writer_pretty(&mut *w, &outcome.report).map_err(std::io::Error::other)?;
        writeln!(w)
    })?;
    output::check_fields(&bodies)?;
    set.write(SOLVE_FILES[1], |w| {
        output::write_vtu_to_with(w, &bodies, vtu)
    })?;
    let svg = output::render_deformed_svg(&scene.title, &bodies)?;
    set.write(SOLVE_FILES[2], |w| w.write_all(svg.as_bytes()))?;
    if let Some(svg) = output::render_pressure_svg(&scene.title, &outcome.report)? {
        set.write(SOLVE_FILES[3], |w| w.write_all(svg.as_bytes()))?;
    }
    set.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_whose_factor_exceeds_the_budget_is_refused_with_exit_3() {
        let scene = load_scene(None).unwrap();
        let limits = MeshLimits::default();
        // Unlimited: the default scene prepares.
        let prepared = prepare_with_budget(&scene, &limits, Some(u64::MAX)).unwrap();
        let n = prepared.qp.dofs();
        // The factor alone holds at least n diagonal values of 8 B: a budget of 8·n bytes
        // cannot hold the run, whatever the ordering.
        let err = prepare_with_budget(&scene, &limits, Some(8 * n as u64)).unwrap_err();
        let RunError::Preflight(PreflightError::FactorTooLarge {
            needed, available, ..
        }) = &err
        else {
            panic!("expected FactorTooLarge, got {err}");
        };
        assert_eq!(*available, 8 * n as u64);
        assert!(*needed > *available);
        let text = err.to_string();
        assert!(text.contains("GiB") && text.contains("nnz(L)"), "{text}");
        assert_eq!(
            crate::exit::classify(&anyhow::Error::new(err)),
            crate::exit::Exit::Resource
        );
    }
}
