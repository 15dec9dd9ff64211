//! `signorini study`: discretisation error against time, for scenes with a known answer.
//!
//! A scene with a `[reference]` (Johnson's Hertz half-width and peak pressure, the patch test's
//! uniform pressure, or Cattaneo–Mindlin partial slip of a frictional Hertz contact: formulas
//! written in the scene, never a finer solve) is solved for
//! every *combination* of contact formulation × mesh kind × element and every mesh size of the
//! plan, with one backend; each solve records its DOFs, its time (mesh + assemble + solve) and
//! its errors against the reference ([`signorini_core::accuracy`]).
//!
//! # The scenes solved
//!
//! * **Mesh size.**  `--hmax h` sets the coarsest body's `hmax` to `h`; every other size of the
//!   scene (other bodies' `hmax`, every `[[body.refine]]` `hmax`) is scaled by the same factor
//!   h / (the scene's largest body hmax).  So a non-matching pair (0.1 / 0.07) stays
//!   non-matching in the same ratio, and a graded mesh keeps its grading as it is refined.
//! * **Formulation.**  Every `[[contact]]` pair gets the combination's formulation.
//! * **Mesh kind.**  `uniform` drops every `[[body.refine]]`; `graded` keeps them (scaled as
//!   above) and applies only to a scene that has some.
//! * **Element.**  `p1` / `q1` is set on the bodies that are axis-aligned rectangles (the only
//!   ones Q1 meshes); other bodies stay P1.  `q1` applies only when some body is such a
//!   rectangle.
//!
//! Combinations that do not apply are skipped and listed ([`StudyOutcome::skipped`]) with the
//! reason.
//!
//! # Files
//!
//! `study.csv` ([`COLUMNS`]) and `accuracy.svg` (error against total time, one panel per error
//! measure, one curve per combination, its fitted convergence rate against h in the legend; see
//! [`plot`]) are one output set ([`crate::outdir`]), written under the
//! directory's lock.  An existing `study.csv` is refused ([`StudyError::Exists`]) unless
//! `overwrite` is set; the old file then stays until the study's first point is written.  After
//! each point the CSV is rewritten (the plot removed, since it no longer matches), so an
//! interrupted study keeps its finished points; the final write puts the CSV and the plot in
//! place together.
//!
//! A point that is not solved (the backend's status, or an error while meshing or assembling,
//! `status = error` with the message) is written like the others and counted in
//! [`StudyOutcome::failed`]; the command then exits with code 2.

use std::path::{Path, PathBuf};

use signorini_core::accuracy::{accuracy, Accuracy};
use signorini_core::mesh::{ElementKind, MeshLimits};
use signorini_core::qp::{QpStatus, SolveOptions};
use signorini_core::scene::{Formulation, Scene, REGION_TOLERANCE};

pub mod plot;
pub mod points;

pub use points::{combination_order, Measure, StudyPoint, COLUMNS, MEASURES};

use crate::backends::{make_backend, BackendKind};
use crate::outdir::{DirLock, OutputSet};
use crate::output::OutputError;
use crate::run::{self, RunError};

/// The CSV file of a study, the primary file of its output set.
pub const STUDY_FILE: &str = "study.csv";

/// The plot of a study.
pub const ACCURACY_PLOT: &str = "accuracy.svg";

/// Uniform or graded meshes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MeshKind {
    /// Every `[[body.refine]]` dropped.
    Uniform,
    /// The scene's `[[body.refine]]` kept (scaled with the body sizes).
    Graded,
}

impl MeshKind {
    /// `uniform` or `graded`.
    pub fn name(self) -> &'static str {
        match self {
            MeshKind::Uniform => "uniform",
            MeshKind::Graded => "graded",
        }
    }
}

impl std::str::FromStr for MeshKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "uniform" => Ok(MeshKind::Uniform),
            "graded" => Ok(MeshKind::Graded),
            other => Err(format!(
                "unknown mesh kind \"{other}\" (expected uniform or graded)"
            )),
        }
    }
}

/// `node-to-segment` or `mortar`, as in the scene file.
pub fn formulation_name(f: Formulation) -> &'static str {
    match f {
        Formulation::NodeToSegment => "node-to-segment",
        Formulation::Mortar => "mortar",
    }
}

/// Parses a formulation name as the scene file spells it.
pub fn parse_formulation(s: &str) -> Result<Formulation, String> {
    match s.trim() {
        "node-to-segment" => Ok(Formulation::NodeToSegment),
        "mortar" => Ok(Formulation::Mortar),
        other => Err(format!(
            "unknown formulation \"{other}\" (expected node-to-segment or mortar)"
        )),
    }
}

/// `p1` or `q1`.
pub fn element_name(e: ElementKind) -> &'static str {
    match e {
        ElementKind::P1 => "p1",
        ElementKind::Q1 => "q1",
    }
}

/// Parses `p1` or `q1`.
pub fn parse_element(s: &str) -> Result<ElementKind, String> {
    match s.trim() {
        "p1" => Ok(ElementKind::P1),
        "q1" => Ok(ElementKind::Q1),
        other => Err(format!("unknown element \"{other}\" (expected p1 or q1)")),
    }
}

/// One formulation × mesh kind × element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Combination {
    /// Contact formulation of every pair.
    pub formulation: Formulation,
    /// Uniform or graded.
    pub mesh: MeshKind,
    /// Element of the rectangular bodies.
    pub element: ElementKind,
}

impl std::fmt::Display for Combination {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}, {}, {}",
            formulation_name(self.formulation),
            self.mesh.name(),
            element_name(self.element)
        )
    }
}

/// What to study.
#[derive(Debug, Clone)]
pub struct StudyPlan {
    /// Sizes of the coarsest body (any order; run coarse to fine).
    pub hmax: Vec<f64>,
    /// Formulations.
    pub formulations: Vec<Formulation>,
    /// Mesh kinds.
    pub meshes: Vec<MeshKind>,
    /// Elements.
    pub elements: Vec<ElementKind>,
    /// The backend every point is solved with.
    pub backend: BackendKind,
    /// Replace an existing `study.csv`.
    pub overwrite: bool,
}

/// A combination that was not run, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Skipped {
    /// The combination.
    pub combination: Combination,
    /// Why it does not apply to the scene.
    pub reason: String,
}

/// What a study wrote.
#[derive(Debug, Clone)]
pub struct StudyOutcome {
    /// `dir/study.csv`.
    pub csv: PathBuf,
    /// `dir/accuracy.svg`, when anything was drawable.
    pub plot: Option<PathBuf>,
    /// Every point, in the order run.
    pub points: Vec<StudyPoint>,
    /// Combinations that do not apply.
    pub skipped: Vec<Skipped>,
    /// Points whose status is not `solved`.
    pub failed: usize,
    /// Fitted convergence rate against h per combination and error measure
    /// (see [`convergence_rates`]).
    pub rates: Vec<Rate>,
}

/// Why a study stopped.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The scene has no `[reference]`.
    #[error("the scene has no [reference] section: `signorini study` compares against analytic values written in the scene (keys `pressure`; or `centre`, `half_width` and `peak_pressure` (Hertz); or `centre`, `radius`, `contact_modulus` and `friction` (Cattaneo–Mindlin); see docs/scene.md)")]
    NoReference,
    /// The plan is inconsistent.
    #[error("{0}")]
    Plan(String),
    /// `study.csv` exists and `overwrite` was not asked for.
    #[error("{} already exists: pass --overwrite to replace it", .0.display())]
    Exists(PathBuf),
    /// Writing the files failed (not `transparent`, so that the exit code's classification
    /// finds the [`OutputError`] in the chain: exit 3).
    #[error("writing the study's files")]
    Output(#[from] OutputError),
}

/// Whether a polygon is an axis-aligned rectangle (4 vertices, each edge horizontal or
/// vertical within `tol`), the shape Q1 meshes (the scene validation's rule).
pub fn is_axis_aligned_rectangle(polygon: &[[f64; 2]], tol: f64) -> bool {
    polygon.len() == 4
        && (0..4).all(|i| {
            let (a, b) = (polygon[i], polygon[(i + 1) % 4]);
            let horizontal = (a[1] - b[1]).abs() <= tol;
            let vertical = (a[0] - b[0]).abs() <= tol;
            horizontal != vertical
        })
}

/// Why `combination` does not apply to `scene`, if it does not.
pub fn not_applicable(scene: &Scene, combination: &Combination) -> Option<String> {
    let tol = REGION_TOLERANCE * scene.size();
    if combination.mesh == MeshKind::Graded && scene.bodies.iter().all(|b| b.refine.is_empty()) {
        return Some("graded: no body has a [[body.refine]] region".into());
    }
    if combination.element == ElementKind::Q1
        && !scene
            .bodies
            .iter()
            .any(|b| is_axis_aligned_rectangle(&b.polygon, tol))
    {
        return Some("q1: no body is an axis-aligned rectangle".into());
    }
    None
}

/// The largest body hmax of the scene: what `--hmax` sets.
fn coarsest(scene: &Scene) -> f64 {
    scene.bodies.iter().map(|b| b.hmax).fold(0.0, f64::max)
}

/// The scene solved for `combination` at size `h` (see the [module docs](self)).
pub fn derive_scene(scene: &Scene, combination: &Combination, h: f64) -> Scene {
    let tol = REGION_TOLERANCE * scene.size();
    let factor = h / coarsest(scene);
    let mut s = scene.clone();
    for b in &mut s.bodies {
        b.hmax *= factor;
        match combination.mesh {
            MeshKind::Uniform => b.refine.clear(),
            MeshKind::Graded => {
                for r in &mut b.refine {
                    r.hmax *= factor;
                }
            }
        }
        if is_axis_aligned_rectangle(&b.polygon, tol) {
            b.element = combination.element;
        }
    }
    for c in &mut s.contacts {
        c.formulation = combination.formulation;
    }
    s
}

/// The smallest element size a scene asks for anywhere.
fn smallest_size(scene: &Scene) -> f64 {
    scene
        .bodies
        .iter()
        .flat_map(|b| std::iter::once(b.hmax).chain(b.refine.iter().map(|r| r.hmax)))
        .fold(f64::INFINITY, f64::min)
}

/// The plan's combinations in order (formulations, then meshes, then elements), duplicates
/// dropped.
pub fn combinations(plan: &StudyPlan) -> Vec<Combination> {
    let mut out: Vec<Combination> = Vec::new();
    for &formulation in &plan.formulations {
        for &mesh in &plan.meshes {
            for &element in &plan.elements {
                let c = Combination {
                    formulation,
                    mesh,
                    element,
                };
                if !out.contains(&c) {
                    out.push(c);
                }
            }
        }
    }
    out
}

/// Checks the plan without touching any file.
pub fn validate_plan(scene: &Scene, plan: &StudyPlan) -> Result<(), StudyError> {
    if scene.reference.is_none() {
        return Err(StudyError::NoReference);
    }
    if let Some(b) = scene.bodies.iter().find(|b| b.imported.is_some()) {
        return Err(StudyError::Plan(format!(
            "body \"{}\" takes its mesh from a file (`mesh`): a study changes every body's mesh size, which a mesh from a file does not have",
            b.name
        )));
    }
    let err = |m: &str| Err(StudyError::Plan(m.to_string()));
    if plan.hmax.is_empty() {
        return err("a study needs at least one --hmax");
    }
    if let Some(h) = plan.hmax.iter().find(|h| !(h.is_finite() && **h > 0.0)) {
        return Err(StudyError::Plan(format!(
            "--hmax values must be positive, got {h}"
        )));
    }
    if plan.formulations.is_empty() || plan.meshes.is_empty() || plan.elements.is_empty() {
        return err("a study needs at least one formulation, mesh kind and element");
    }
    if !plan.backend.available() {
        return Err(StudyError::Plan(format!(
            "backend \"{}\" is not compiled in",
            plan.backend
        )));
    }
    Ok(())
}

/// One fitted rate: the slope of log |error| against log h over a combination's solved points.
#[derive(Debug, Clone, PartialEq)]
pub struct Rate {
    /// `formulation, mesh, element`.
    pub combination: String,
    /// The error measure (a [`MEASURES`] name).
    pub measure: &'static str,
    /// The exponent p of |error| ≈ C hᵖ (`None` with fewer than two usable points).
    pub rate: Option<f64>,
    /// Points fitted.
    pub points: usize,
}

/// The fitted convergence rate of every combination and measure that has a value, from the
/// solved points: [`crate::plots::fit_slope`] of (hmax, |error|).
pub fn convergence_rates(points: &[StudyPoint]) -> Vec<Rate> {
    let mut out = Vec::new();
    for combination in combination_order(points) {
        for (measure, read) in MEASURES {
            let pts: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.solved() && p.combination() == combination)
                .filter_map(|p| read(p).map(|e| (p.hmax, e.abs())))
                .collect();
            if pts.is_empty() {
                continue;
            }
            out.push(Rate {
                combination: combination.clone(),
                measure,
                rate: crate::plots::fit_slope(&pts),
                points: pts.len(),
            });
        }
    }
    out
}

/// Writes `points` as `study.csv` (header first, even without points).
fn write_csv(w: &mut dyn std::io::Write, points: &[StudyPoint]) -> std::io::Result<()> {
    let mut csv = csv::WriterBuilder::new().has_headers(false).from_writer(w);
    csv.write_record(COLUMNS)?;
    for p in points {
        csv.serialize(p).map_err(std::io::Error::other)?;
    }
    csv.flush()
}

/// Reads the points of a `study.csv`.
pub fn read_points(path: &Path) -> Result<Vec<StudyPoint>, OutputError> {
    crate::output::read_csv(path)
}

const MEMBERS: [&str; 2] = [STUDY_FILE, ACCURACY_PLOT];

/// Replaces `study.csv` by `points` and removes the plot (it no longer matches).
fn checkpoint(lock: &DirLock, points: &[StudyPoint]) -> Result<(), OutputError> {
    let mut set = OutputSet::new(lock, Some(STUDY_FILE), &MEMBERS)?;
    set.write(STUDY_FILE, |w| write_csv(w, points))?;
    set.commit().map(drop)
}

/// The errors of an [`Accuracy`] in a point.
fn fill_errors(point: &mut StudyPoint, acc: &Accuracy) {
    point.half_width = acc.half_width.map(|e| e.computed);
    point.error_half_width = acc.half_width.map(|e| e.error());
    point.peak_pressure = acc.peak_pressure.map(|e| e.computed);
    point.error_peak_pressure = acc.peak_pressure.map(|e| e.error());
    point.peak_nodal_pressure = acc.peak_nodal_pressure.map(|e| e.computed);
    point.error_peak_nodal_pressure = acc.peak_nodal_pressure.map(|e| e.error());
    point.pressure_deviation = acc.pressure_deviation;
    point.stick_half_width = acc.stick_half_width.map(|e| e.computed);
    point.error_stick_half_width = acc.stick_half_width.map(|e| e.error());
    point.error_tangential_traction = acc.tangential_traction;
}

/// Solves one point; errors of the run become a point with status `error`.
fn solve_point(
    scene: &Scene,
    combination: &Combination,
    h: f64,
    plan: &StudyPlan,
    options: &SolveOptions,
    limits: &MeshLimits,
) -> Result<StudyPoint, StudyError> {
    let s = derive_scene(scene, combination, h);
    let mut point = StudyPoint {
        formulation: formulation_name(combination.formulation).into(),
        mesh: combination.mesh.name().into(),
        element: element_name(combination.element).into(),
        hmax: h,
        hmin: smallest_size(&s),
        dofs: 0,
        constraints: 0,
        backend: plan.backend.name().into(),
        status: "error".into(),
        mesh_s: f64::NAN,
        assemble_s: f64::NAN,
        solve_s: f64::NAN,
        total_s: f64::NAN,
        half_width: None,
        error_half_width: None,
        peak_pressure: None,
        error_peak_pressure: None,
        peak_nodal_pressure: None,
        error_peak_nodal_pressure: None,
        pressure_deviation: None,
        stick_half_width: None,
        error_stick_half_width: None,
        error_tangential_traction: None,
        message: String::new(),
    };
    // `auto` is built here rather than by `make_backend`, to read which backend it chose.
    let mut auto = crate::auto::AutoBackend::default();
    let mut other = match plan.backend {
        BackendKind::Auto => None,
        kind => Some(make_backend(kind).map_err(|e| StudyError::Plan(e.to_string()))?),
    };
    let result = match other.as_mut() {
        Some(b) => run::solve_scene(&s, b.as_mut(), options, limits),
        None => run::solve_scene(&s, &mut auto, options, limits),
    };
    let outcome = match result {
        Ok(mut o) => {
            if let Some(record) = auto.record() {
                record.annotate(&mut o.report);
            }
            o
        }
        // Output errors are the machine's, not the point's: they stop the study.
        Err(RunError::Output(e)) => return Err(e.into()),
        Err(e) => {
            point.message = e.to_string();
            return Ok(point);
        }
    };
    let r = &outcome.report;
    point.dofs = r.dofs;
    point.constraints = r.constraints;
    point.backend = r.chosen.clone().unwrap_or_else(|| r.backend.clone());
    point.status = r.status.clone();
    point.mesh_s = r.timing_s.mesh;
    point.assemble_s = r.timing_s.assemble;
    point.solve_s = r.timing_s.solve;
    point.total_s = r.timing_s.mesh + r.timing_s.assemble + r.timing_s.solve;
    if outcome.solution.status != QpStatus::Solved {
        point.message = r
            .message
            .clone()
            .unwrap_or_else(|| format!("backend said {}", r.backend_status));
    }
    // The study refused scenes without a reference before running.
    if let Some(reference) = &s.reference {
        match accuracy(reference, r) {
            Ok(acc) => fill_errors(&mut point, &acc),
            Err(e) => {
                if point.message.is_empty() {
                    point.message = e.to_string();
                }
            }
        }
    }
    Ok(point)
}

/// Runs the study into `dir/study.csv` and `dir/accuracy.svg` (see the [module docs](self));
/// `progress(done, total, what)` after each point.  Plot headings use the part of the scene
/// title before any colon.
pub fn study(
    scene: &Scene,
    plan: &StudyPlan,
    options: &SolveOptions,
    limits: &MeshLimits,
    dir: &Path,
    mut progress: impl FnMut(usize, usize, &str),
) -> Result<StudyOutcome, StudyError> {
    validate_plan(scene, plan)?;
    let csv_path = dir.join(STUDY_FILE);
    // Read-only checks first, so that a refusal does not even create the directory.
    if csv_path.exists() && !plan.overwrite {
        return Err(StudyError::Exists(csv_path));
    }
    let lock = DirLock::acquire(dir)?;
    if std::fs::symlink_metadata(&csv_path).is_ok() && !plan.overwrite {
        return Err(StudyError::Exists(csv_path));
    }
    let mut hmaxes = plan.hmax.clone();
    hmaxes.sort_by(|a, b| b.total_cmp(a));
    hmaxes.dedup();
    let mut skipped = Vec::new();
    let mut todo = Vec::new();
    for c in combinations(plan) {
        match not_applicable(scene, &c) {
            Some(reason) => skipped.push(Skipped {
                combination: c,
                reason,
            }),
            None => todo.push(c),
        }
    }
    let total = todo.len() * hmaxes.len();
    let mut points = Vec::with_capacity(total);
    for c in &todo {
        for &h in &hmaxes {
            let point = solve_point(scene, c, h, plan, options, limits)?;
            points.push(point);
            checkpoint(&lock, &points)?;
            progress(points.len(), total, &format!("{c} hmax {h}"));
        }
    }
    let short = scene.title.split(':').next().unwrap_or(&scene.title).trim();
    let svg = plot::render_accuracy(&points, short)?;
    let mut set = OutputSet::new(&lock, Some(STUDY_FILE), &MEMBERS)?;
    let csv = set.write(STUDY_FILE, |w| write_csv(w, &points))?;
    let plot = match &svg {
        Some(svg) => Some(set.write(ACCURACY_PLOT, |w| w.write_all(svg.as_bytes()))?),
        None => None,
    };
    set.commit()?;
    let failed = points.iter().filter(|p| !p.solved()).count();
    Ok(StudyOutcome {
        csv,
        plot,
        rates: convergence_rates(&points),
        points,
        skipped,
        failed,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_blocks() -> Scene {
        Scene::from_toml(
            r#"
            [[body]]
            name = "upper"
            polygon = [[0, 1], [1, 1], [1, 2], [0, 2]]
            hmax = 0.07
            young = 2.0
            poisson = 0.0
            [[body.refine]]
            region = [0, 1, 1, 1.1]
            hmax = 0.035
            [[body]]
            name = "lower"
            polygon = [[0, 0], [1, 0], [1, 1], [0.5, 1], [0, 1]]
            hmax = 0.1
            young = 1.0
            poisson = 0.0
            [[dirichlet]]
            body = "lower"
            region = [0, 1, 0, 0]
            [[dirichlet]]
            body = "upper"
            region = [0, 1, 2, 2]
            value = [0, -0.015]
            [[contact]]
            bodies = ["upper", "lower"]
            [reference]
            pressure = 0.01
            "#,
        )
        .unwrap()
    }

    #[test]
    fn derived_scenes_scale_every_size_by_one_factor_and_switch_only_rectangles() {
        let scene = two_blocks();
        let c = Combination {
            formulation: Formulation::Mortar,
            mesh: MeshKind::Graded,
            element: ElementKind::Q1,
        };
        let s = derive_scene(&scene, &c, 0.05);
        // The coarsest body (0.1) becomes 0.05: factor 1/2 on everything.
        assert!((s.bodies[1].hmax - 0.05).abs() < 1e-15);
        assert!((s.bodies[0].hmax - 0.035).abs() < 1e-15);
        assert!((s.bodies[0].refine[0].hmax - 0.0175).abs() < 1e-15);
        assert!((smallest_size(&s) - 0.0175).abs() < 1e-15);
        // Only the rectangle is switched to Q1; the pentagon stays P1.
        assert_eq!(s.bodies[0].element, ElementKind::Q1);
        assert_eq!(s.bodies[1].element, ElementKind::P1);
        assert!(s
            .contacts
            .iter()
            .all(|p| p.formulation == Formulation::Mortar));
        let u = derive_scene(
            &scene,
            &Combination {
                mesh: MeshKind::Uniform,
                ..c
            },
            0.05,
        );
        assert!(u.bodies.iter().all(|b| b.refine.is_empty()));
    }

    #[test]
    fn combinations_that_do_not_apply_say_why() {
        let mut scene = two_blocks();
        let graded_q1 = Combination {
            formulation: Formulation::NodeToSegment,
            mesh: MeshKind::Graded,
            element: ElementKind::Q1,
        };
        assert_eq!(not_applicable(&scene, &graded_q1), None);
        scene.bodies[0].refine.clear();
        assert!(not_applicable(&scene, &graded_q1)
            .unwrap()
            .contains("[[body.refine]]"));
        scene.bodies[0].polygon[2] = [1.0, 2.1];
        let uniform_q1 = Combination {
            mesh: MeshKind::Uniform,
            ..graded_q1
        };
        assert!(not_applicable(&scene, &uniform_q1)
            .unwrap()
            .contains("axis-aligned rectangle"));
    }

    #[test]
    fn a_scene_without_reference_is_refused_naming_the_section() {
        let mut scene = two_blocks();
        scene.reference = None;
        let plan = StudyPlan {
            hmax: vec![0.1],
            formulations: vec![Formulation::Mortar],
            meshes: vec![MeshKind::Uniform],
            elements: vec![ElementKind::P1],
            backend: BackendKind::Clarabel,
            overwrite: false,
        };
        let err = validate_plan(&scene, &plan).unwrap_err();
        assert!(err.to_string().contains("[reference]"), "{err}");
    }

    #[test]
    fn the_header_is_the_points_fields() {
        let p = StudyPoint {
            formulation: "mortar".into(),
            mesh: "uniform".into(),
            element: "p1".into(),
            hmax: 0.1,
            hmin: 0.1,
            dofs: 1,
            constraints: 1,
            backend: "b".into(),
            status: "solved".into(),
            mesh_s: 0.0,
            assemble_s: 0.0,
            solve_s: 0.0,
            total_s: 0.0,
            half_width: None,
            error_half_width: None,
            peak_pressure: None,
            error_peak_pressure: None,
            peak_nodal_pressure: None,
            error_peak_nodal_pressure: None,
            pressure_deviation: Some(0.1),
            stick_half_width: Some(0.02),
            error_stick_half_width: Some(-0.01),
            error_tangential_traction: Some(0.04),
            message: String::new(),
        };
        let mut buf = Vec::new();
        write_csv(&mut buf, std::slice::from_ref(&p)).unwrap();
        let text = String::from_utf8(buf).unwrap();
        assert_eq!(text.lines().next().unwrap(), COLUMNS.join(","));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(STUDY_FILE);
        std::fs::write(&path, &text).unwrap();
        assert_eq!(read_points(&path).unwrap(), vec![p]);
    }

    #[test]
    fn rates_are_fitted_per_combination_and_measure_from_solved_points() {
        let point = |h: f64, e: f64, status: &str| StudyPoint {
            formulation: "mortar".into(),
            mesh: "graded".into(),
            element: "p1".into(),
            hmax: h,
            hmin: h,
            dofs: 1,
            constraints: 1,
            backend: "b".into(),
            status: status.into(),
            mesh_s: 0.0,
            assemble_s: 0.0,
            solve_s: 0.0,
            total_s: 1.0,
            half_width: None,
            error_half_width: Some(-e),
            peak_pressure: None,
            error_peak_pressure: None,
            peak_nodal_pressure: None,
            error_peak_nodal_pressure: None,
            pressure_deviation: None,
            stick_half_width: None,
            error_stick_half_width: None,
            error_tangential_traction: None,
            message: String::new(),
        };
        // |error| = 3 h²: rate 2 whatever the sign; the unsolved point (off the line) is ignored.
        let pts = vec![
            point(0.1, 0.03, "solved"),
            point(0.05, 0.0075, "solved"),
            point(0.025, 0.001875, "solved"),
            point(0.0125, 1.0, "max-iterations"),
        ];
        let rates = convergence_rates(&pts);
        assert_eq!(rates.len(), 1);
        assert_eq!(rates[0].measure, "half-width a");
        assert_eq!(rates[0].points, 3);
        assert!((rates[0].rate.unwrap() - 2.0).abs() < 1e-12);
    }
}
