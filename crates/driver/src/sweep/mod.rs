//! `signorini sweep`: cost and accuracy as the mesh is refined, per backend and tolerance.
//!
//! For each hmax (coarse to fine) the scene is meshed and assembled (`repeat` times, median
//! times), the floor is timed (one unconstrained factor + solve of the same A), then every
//! (tolerance, backend) point is solved `repeat` times.  Tolerances run tightest first so that the
//! reference of a mesh (the solved answer with the smallest residuals at the tightest tolerance)
//! is known before the looser points are measured against it.  At the end `error_vs_finest` is
//! filled in: the relative difference to the finest mesh's reference, in max displacement and at
//! every probe.
//!
//! # Files
//!
//! `sweep.csv` and its plots ([`crate::plots::PLOT_FILES`]) are one output set (see
//! [`crate::outdir`]), written under the output directory's lock:
//!
//! * The plan is validated ([`validate_plan`]) before any file is touched.
//! * An existing `sweep.csv` is never deleted or truncated unasked: the sweep refuses
//!   ([`SweepError::Exists`]) unless `resume` (add the missing points) or `overwrite` (replace
//!   it) is set.  With `overwrite` the old file stays until the new sweep writes its first point.
//! * With `resume`, the existing file is verified first ([`read_for_resume`]): the header, a
//!   line break after every line, each row readable, its `scene_hash` equal to this scene's, its
//!   hmax, backend and tolerance part of the plan, and no point twice; a foreign or corrupt file
//!   is refused naming the line.
//! * After each point the whole CSV is rewritten through an [`OutputSet`] (a complete file,
//!   replaced atomically, and the previous plots removed since they no longer match), so an
//!   interrupted sweep keeps every finished point and `resume` skips them.  The final write
//!   replaces `sweep.csv` and the plots together.
//!
//! * `shard.json` (with `--shard`) and `solutions.pvd` (with `--vtu`) are members of the same
//!   set; a run that does not write them removes an earlier run's.
//!
//! # Shards and merging
//!
//! `--shard I/N` runs the plan's points `I, I + N, I + 2N, …` (numbered from 1 in plan order:
//! hmax coarse to fine, tolerances tightest first, backends as given); see [`shard`] for the
//! files a shard adds (`shard.json`, `displacements/<p>.u`) and [`merge`] for
//! `signorini sweep merge`, which checks that the shards form one study and writes the merged
//! `sweep.csv` and plots.  A shard leaves both error columns empty (they need points of other
//! shards); the merge computes them from the stored displacements, residuals and probes with
//! the same functions an unsharded sweep uses, so the merged file equals the unsharded one
//! apart from the times and memory.  A backend that hits the time limit is skipped on the finer
//! meshes *of the same shard* only (a shard does not see the others' points).
//!
//! # Solutions (`--vtu`)
//!
//! Every point run writes its solution as `solutions/<point>.vtu` ([`solution_file_name`],
//! each file its own output set inside `solutions/`, written before the point's row) and the
//! final write adds [`SOLUTIONS_FILE`], a ParaView collection (PVD) listing the points of
//! `sweep.csv` whose file exists, with `timestep` = the point's number in the plan.
//!
//! # Scene hash
//!
//! The `scene_hash` column ([`scene_hash`]) is the FNV-1a 64-bit hash, as 16 lowercase hex
//! digits, of the UTF-8 text [`canonical_scene_text`] gives for the validated scene: every field
//! that shapes the problem or the reported numbers (plane, thickness, gravity, bodies with their
//! names, polygons, elements, materials and hmax, Dirichlet and Neumann data, contact pairs,
//! probes), floats written with Rust's shortest round-trip `{:e}`; not the title; and the hmax
//! of the swept bodies written as `swept`, so the hash does not depend on the swept sizes but
//! does on which bodies are swept.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::time::Duration;

use serde::{Deserialize, Serialize};
use signorini_core::mesh::{estimate_elements_refined, MeshLimits};
use signorini_core::qp::{QpStatus, SolveOptions};
use signorini_core::report::interpolate;
use signorini_core::scene::Scene;
use signorini_core::solve::{self, Solution};

use crate::backends::{make_backend, BackendKind};
use crate::outdir::{DirLock, OutputSet};
use crate::output::OutputError;
use crate::run::{self, RunError};

pub mod merge;
pub mod shard;

use shard::{Manifest, Shard};

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
    /// Keep the points of an existing `sweep.csv` (after verifying it) and run the others.
    pub resume: bool,
    /// Replace an existing `sweep.csv` (once the new sweep writes its first point).
    pub overwrite: bool,
    /// Run only this shard's points (see [`shard`]); `None`: every point.
    pub shard: Option<Shard>,
    /// Write each point's solution as `solutions/<point>.vtu` and the collection
    /// `solutions.pvd` (see [`SOLUTIONS_FILE`]).
    pub vtu: bool,
}

/// The CSV file of a sweep, the primary file of its output set.
pub const SWEEP_FILE: &str = "sweep.csv";

/// The ParaView collection of the points' solutions (with `--vtu`): a PVD file listing
/// `solutions/<point>.vtu` ([`solution_file_name`]) for every point of `sweep.csv` whose
/// solution file exists, in plan order, each with `timestep` = the point's number in the plan
/// (from 1; see [`shard`]), so ParaView's time slider steps through the points.
pub const SOLUTIONS_FILE: &str = "solutions.pvd";

/// The subdirectory of the points' VTU files (with `--vtu`).
pub const SOLUTIONS_DIR: &str = "solutions";

/// What a sweep wrote.
#[derive(Debug, Clone)]
pub struct SweepOutcome {
    /// `dir/sweep.csv`.
    pub csv: PathBuf,
    /// The plots written (see [`crate::plots::plot_sweep`]).
    pub plots: Vec<PathBuf>,
    /// Every point of the file, resumed ones included.
    pub points: Vec<Point>,
    /// Points of the file whose status is not `solved`.
    pub failed: usize,
    /// Points of the plan that were not run: their backend hit the time limit on a coarser mesh.
    pub skipped: usize,
    /// This scene's [`scene_hash`].
    pub scene_hash: String,
    /// Other files of the set written: `shard.json` (with a shard), `solutions.pvd` (with
    /// `vtu`).
    pub files: Vec<PathBuf>,
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
    /// `sweep.csv` exists and neither `resume` nor `overwrite` was asked for.
    #[error("{} already exists: pass --resume to add the missing points to it, or --overwrite to replace it", .0.display())]
    Exists(PathBuf),
    /// The existing `sweep.csv` cannot be resumed: it belongs to another scene or plan, or it is
    /// damaged.
    #[error("cannot resume {}: line {line}: {reason} (pass --overwrite to replace the file)", path.display())]
    Resume {
        /// The file.
        path: PathBuf,
        /// 1-based line of the file.
        line: u64,
        /// What is wrong there.
        reason: String,
    },
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
    /// The backend's own verdict before the core's check.
    pub backend_status: String,
    /// Probe displacements `name:ux:uy` joined by `;`.
    pub probes: String,
    /// [`scene_hash`] of the scene the point was solved for.
    pub scene_hash: String,
    /// Fill-reducing ordering of the floor's factor (`amd` or `metis`).
    pub floor_ordering: String,
    /// Nonzeros of the floor's Cholesky factor L (lower triangle, diagonal included).
    pub floor_nnz_l: usize,
}

/// The header of `sweep.csv`: [`Point`]'s fields in order.
pub const COLUMNS: [&str; 24] = [
    "hmax",
    "dofs",
    "constraints",
    "backend",
    "tol",
    "status",
    "iterations",
    "mesh_s",
    "assemble_s",
    "solve_s",
    "floor_s",
    "ratio_to_floor",
    "error_vs_reference",
    "error_vs_finest",
    "max_displacement",
    "peak_rss_mb",
    "max_penetration",
    "stationarity",
    "complementarity",
    "backend_status",
    "probes",
    "scene_hash",
    "floor_ordering",
    "floor_nnz_l",
];

impl Point {
    /// The point as a row for the plots.
    fn to_row(&self) -> crate::plots::SweepRow {
        crate::plots::SweepRow {
            hmax: self.hmax,
            dofs: self.dofs,
            constraints: self.constraints,
            backend: self.backend.clone(),
            tol: self.tol,
            status: self.status.clone(),
            iterations: self.iterations,
            mesh_s: self.mesh_s,
            assemble_s: self.assemble_s,
            solve_s: self.solve_s,
            floor_s: self.floor_s,
            ratio_to_floor: self.ratio_to_floor,
            error_vs_reference: self.error_vs_reference,
            error_vs_finest: self.error_vs_finest,
            max_displacement: self.max_displacement,
            peak_rss_mb: self.peak_rss_mb,
            max_penetration: self.max_penetration,
            stationarity: self.stationarity,
            complementarity: self.complementarity,
        }
    }
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

/// The scene with hmax set for the named bodies (all when `bodies` is empty).  A body's
/// `[[body.refine]]` sizes scale with it (each keeps its ratio to the body's hmax), so a graded
/// mesh stays graded the same way at every point of the sweep.
pub fn with_hmax(scene: &Scene, bodies: &[String], hmax: f64) -> Scene {
    let mut s = scene.clone();
    for b in &mut s.bodies {
        if bodies.is_empty() || bodies.contains(&b.name) {
            let factor = hmax / b.hmax;
            for r in &mut b.refine {
                r.hmax *= factor;
            }
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

fn key(hmax: f64, backend: &str, tol: f64) -> String {
    format!("{hmax:e}|{backend}|{tol:e}")
}

/// The canonical text of `scene` that [`scene_hash`] hashes (see the [module docs](self)):
/// one line per item, names quoted as Rust string literals, floats as `{:e}`, the hmax of the
/// bodies in `swept` (all bodies when empty) written as `swept`, the title left out.
pub fn canonical_scene_text(scene: &Scene, swept: &[String]) -> String {
    use std::fmt::Write as _;
    let mut t = String::from("signorini scene v1\n");
    let pt = |p: &[f64; 2]| format!("{:e} {:e}", p[0], p[1]);
    let bx = |r: &[f64; 4]| format!("{:e} {:e} {:e} {:e}", r[0], r[1], r[2], r[3]);
    // Writing to a String cannot fail.
    let _ = writeln!(t, "plane {:?}", scene.plane);
    let _ = writeln!(t, "thickness {:e}", scene.thickness);
    match &scene.gravity {
        Some(g) => {
            let _ = writeln!(t, "gravity {}", pt(g));
        }
        None => t.push_str("gravity none\n"),
    }
    for b in &scene.bodies {
        let hmax = if swept.is_empty() || swept.contains(&b.name) {
            "swept".to_string()
        } else {
            format!("{:e}", b.hmax)
        };
        let density = b.density.map_or("none".into(), |d| format!("{d:e}"));
        let polygon: Vec<String> = b.polygon.iter().map(pt).collect();
        let _ = writeln!(
            t,
            "body {:?} element {:?} hmax {hmax} young {:e} poisson {:e} density {density} polygon {}",
            b.name,
            b.element,
            b.young,
            b.poisson,
            polygon.join(", ")
        );
    }
    for d in &scene.dirichlet {
        let _ = writeln!(
            t,
            "dirichlet body {} region {} value {} components {} {}",
            d.body,
            bx(&d.region),
            pt(&d.value),
            d.components[0],
            d.components[1]
        );
    }
    for n in &scene.neumann {
        let c = &n.traction.coefficients;
        let _ = writeln!(
            t,
            "neumann body {} region {} traction {:e} {:e} {:e} {:e} {:e} {:e}",
            n.body,
            bx(&n.region),
            c[0][0],
            c[0][1],
            c[0][2],
            c[1][0],
            c[1][1],
            c[1][2]
        );
    }
    for c in &scene.contacts {
        let region = c.region.as_ref().map_or("none".into(), bx);
        let slave = c.slave.map_or("none".into(), |s| s.to_string());
        let _ = writeln!(
            t,
            "contact bodies {} {} region {region} slave {slave}",
            c.bodies[0], c.bodies[1]
        );
    }
    for p in &scene.probes {
        let _ = writeln!(
            t,
            "probe {:?} body {} point {}",
            p.name,
            p.body,
            pt(&p.point)
        );
    }
    t
}

/// FNV-1a, 64 bits.
fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The `scene_hash` column: FNV-1a 64 of [`canonical_scene_text`], 16 lowercase hex digits.
/// Independent of the swept bodies' hmax (and of the title).
pub fn scene_hash(scene: &Scene, swept: &[String]) -> String {
    format!(
        "{:016x}",
        fnv1a64(canonical_scene_text(scene, swept).as_bytes())
    )
}

/// The plan's grid: hmax coarse to fine, tolerances tightest first, backends in the given order;
/// duplicates dropped.
fn grid(plan: &SweepPlan) -> (Vec<f64>, Vec<f64>, Vec<BackendKind>) {
    let mut hmaxes = plan.hmax.clone();
    hmaxes.sort_by(|a, b| b.total_cmp(a));
    hmaxes.dedup();
    let mut tols = plan.tols.clone();
    tols.sort_by(f64::total_cmp);
    tols.dedup();
    let mut backends: Vec<BackendKind> = Vec::new();
    for &b in &plan.backends {
        if !backends.contains(&b) {
            backends.push(b);
        }
    }
    (hmaxes, tols, backends)
}

/// Checks the plan against the scene without touching any file: at least one hmax, backend and
/// tolerance; hmax values positive and finite; tolerances in (0, 1); `repeat` ≥ 1; known body
/// names; not both `resume` and `overwrite`; and at every hmax an estimated total element count
/// (all bodies) within `limits.max_elements`.
pub fn validate_plan(
    scene: &Scene,
    plan: &SweepPlan,
    limits: &MeshLimits,
) -> Result<(), SweepError> {
    let plan_err = |m: String| Err(SweepError::Plan(m));
    if plan.hmax.is_empty() || plan.backends.is_empty() || plan.tols.is_empty() {
        return plan_err("a sweep needs at least one hmax, one backend and one tolerance".into());
    }
    if let Some(h) = plan.hmax.iter().find(|h| !(h.is_finite() && **h > 0.0)) {
        return plan_err(format!("--hmax values must be positive, got {h}"));
    }
    if let Some(t) = plan
        .tols
        .iter()
        .find(|t| !(t.is_finite() && **t > 0.0 && **t < 1.0))
    {
        return plan_err(format!("--tol values must lie in (0, 1), got {t}"));
    }
    if plan.repeat == 0 {
        return plan_err("--repeat must be at least 1, got 0".into());
    }
    if plan.resume && plan.overwrite {
        return plan_err("--resume and --overwrite exclude each other".into());
    }
    for name in &plan.bodies {
        if scene.body_index(name).is_none() {
            return plan_err(format!("--bodies names an unknown body \"{name}\""));
        }
    }
    // A body meshed by Gmsh has no hmax to sweep: every point would repeat its mesh.
    let swept =
        |b: &&signorini_core::scene::Body| plan.bodies.is_empty() || plan.bodies.contains(&b.name);
    if let Some(b) = scene
        .bodies
        .iter()
        .filter(swept)
        .find(|b| b.imported.is_some())
    {
        return plan_err(format!(
            "body \"{}\" takes its mesh from a file (`mesh`), so its hmax cannot be swept; name the polygon bodies to sweep with --bodies",
            b.name
        ));
    }
    for &h in &plan.hmax {
        let s = with_hmax(scene, &plan.bodies, h);
        let total = s
            .bodies
            .iter()
            .map(|b| estimate_elements_refined(&b.polygon, b.hmax, &b.refine, b.element))
            .fold(0usize, usize::saturating_add);
        if total > limits.max_elements {
            return plan_err(format!(
                "--hmax {h}: the scene would have ~{total} elements, more than --max-elements {}",
                limits.max_elements
            ));
        }
    }
    Ok(())
}

/// Reads an existing `sweep.csv` for `--resume` and verifies it against this scene and plan:
/// a header equal to [`COLUMNS`] (a file without `scene_hash` was written by an older version),
/// every line ended by a line break, every row complete and readable, its `scene_hash` equal to
/// `hash`, its hmax, backend and tolerance part of the plan, and no (hmax, backend, tolerance)
/// twice.  The first violation is refused with [`SweepError::Resume`] naming its line.
pub fn read_for_resume(
    path: &Path,
    hash: &str,
    plan: &SweepPlan,
) -> Result<Vec<Point>, SweepError> {
    let refuse = |line: u64, reason: String| SweepError::Resume {
        path: path.to_path_buf(),
        line,
        reason,
    };
    let bytes = std::fs::read(path).map_err(|source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let the_grid = grid(plan);
    let (hmaxes, tols, backends) = &the_grid;
    let mut seen: HashMap<String, u64> = HashMap::new();
    let mut points = Vec::new();
    read_rows_strict(bytes, refuse, |line, p| {
        if p.scene_hash != hash {
            return Err(refuse(
                line,
                format!(
                    "scene_hash {} is not this scene's {hash}: the file belongs to another scene (or other --bodies)",
                    p.scene_hash
                ),
            ));
        }
        if !hmaxes.iter().any(|h| h.to_bits() == p.hmax.to_bits()) {
            return Err(refuse(line, format!("hmax {} is not in --hmax", p.hmax)));
        }
        if !tols.iter().any(|t| t.to_bits() == p.tol.to_bits()) {
            return Err(refuse(line, format!("tol {:e} is not in --tol", p.tol)));
        }
        if !backends.iter().any(|b| b.name() == p.backend) {
            return Err(refuse(
                line,
                format!("backend \"{}\" is not in --backends", p.backend),
            ));
        }
        if let (Some(s), Some(k)) = (plan.shard, plan_index(&the_grid, &p)) {
            if !s.owns(k) {
                return Err(refuse(
                    line,
                    format!(
                        "point {k} of the plan belongs to shard {}/{}, not to this shard {s}",
                        Shard::of_point(k, s.count),
                        s.count
                    ),
                ));
            }
        }
        if let Some(first) = seen.insert(key(p.hmax, &p.backend, p.tol), line) {
            return Err(refuse(
                line,
                format!(
                    "repeats the point of line {first} (hmax {}, {}, tol {:e})",
                    p.hmax, p.backend, p.tol
                ),
            ));
        }
        points.push(p);
        Ok(())
    })?;
    Ok(points)
}

/// `sweep.csv`'s bytes checked and read row by row, for `--resume` and `sweep merge`: UTF-8
/// text ending in a line break, the header [`COLUMNS`] (a file without `scene_hash`, or with an
/// older version's shorter header, is named as such), every row complete and readable with a
/// status; each row is handed to `row` with its line.  Every refusal is `refuse(line, reason)`
/// (lines from 1); the first one stops the reading.
pub(crate) fn read_rows_strict<E>(
    bytes: Vec<u8>,
    refuse: impl Fn(u64, String) -> E,
    mut row: impl FnMut(u64, Point) -> Result<(), E>,
) -> Result<(), E> {
    let text = String::from_utf8(bytes).map_err(|e| {
        let line = 1 + e.as_bytes()[..e.utf8_error().valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count() as u64;
        refuse(line, "not UTF-8 text".into())
    })?;
    if text.is_empty() {
        return Err(refuse(1, "the file is empty (no header)".into()));
    }
    if !text.ends_with('\n') {
        let line = 1 + text.matches('\n').count() as u64;
        return Err(refuse(
            line,
            "the line is incomplete (no line break at the end of the file)".into(),
        ));
    }
    let mut reader = csv::ReaderBuilder::new().from_reader(text.as_bytes());
    let header = reader
        .headers()
        .map_err(|e| refuse(1, format!("unreadable header: {e}")))?
        .clone();
    if !header.iter().any(|h| h == "scene_hash") {
        return Err(refuse(
            1,
            "no scene_hash column: the file was not written by this version of signorini's sweep"
                .into(),
        ));
    }
    let columns: Vec<&str> = header.iter().collect();
    if columns.len() < COLUMNS.len() && COLUMNS.starts_with(&columns) {
        return Err(refuse(
            1,
            format!(
                "the file was written by an older version of signorini's sweep: its header lacks the last column(s) {}",
                COLUMNS[columns.len()..].join(",")
            ),
        ));
    }
    if !header.iter().eq(COLUMNS.iter().copied()) {
        return Err(refuse(
            1,
            format!(
                "the header is not sweep.csv's: expected {}",
                COLUMNS.join(",")
            ),
        ));
    }
    let mut record = csv::StringRecord::new();
    loop {
        let more = reader.read_record(&mut record).map_err(|e| {
            let line = e.position().map_or(0, csv::Position::line);
            match e.kind() {
                csv::ErrorKind::UnequalLengths {
                    expected_len, len, ..
                } => refuse(
                    line,
                    format!("{len} fields, but the header has {expected_len}"),
                ),
                _ => refuse(line, e.to_string()),
            }
        })?;
        if !more {
            return Ok(());
        }
        let line = record.position().map_or(0, csv::Position::line);
        let p: Point = record
            .deserialize(Some(&header))
            .map_err(|e| refuse(line, format!("unreadable row: {e}")))?;
        if p.status.trim().is_empty() {
            return Err(refuse(line, "empty status".into()));
        }
        row(line, p)?;
    }
}

/// Writes `points` as `sweep.csv` (header first, even without points).
fn write_csv(w: &mut dyn std::io::Write, points: &[Point]) -> std::io::Result<()> {
    let mut csv = csv::WriterBuilder::new().has_headers(false).from_writer(w);
    csv.write_record(COLUMNS)?;
    for p in points {
        csv.serialize(p).map_err(std::io::Error::other)?;
    }
    csv.flush()
}

/// The files of a sweep's output set: the CSV (primary), the plots, the shard's manifest and
/// the solutions' collection (the last two are removed when a run does not write them).
fn sweep_members() -> Vec<&'static str> {
    std::iter::once(SWEEP_FILE)
        .chain(crate::plots::PLOT_FILES)
        .chain([shard::MANIFEST_FILE, SOLUTIONS_FILE])
        .collect()
}

/// Replaces `sweep.csv` by `points` (and `shard.json` by `manifest`, if any) and removes the
/// plots (they no longer match).
fn checkpoint(
    lock: &DirLock,
    points: &[Point],
    manifest: Option<&Manifest>,
) -> Result<(), OutputError> {
    let mut set = OutputSet::new(lock, Some(SWEEP_FILE), &sweep_members())?;
    set.write(SWEEP_FILE, |w| write_csv(w, points))?;
    if let Some(m) = manifest {
        set.write(shard::MANIFEST_FILE, |w| m.write(w))?;
    }
    set.commit().map(drop)
}

/// The number (from 1) of the point (hmax, backend, tol) in the plan order of `grid` (see
/// [`shard`]), if it is part of the grid.
fn plan_index(grid: &(Vec<f64>, Vec<f64>, Vec<BackendKind>), p: &Point) -> Option<usize> {
    let (hmaxes, tols, backends) = grid;
    let ih = hmaxes
        .iter()
        .position(|h| h.to_bits() == p.hmax.to_bits())?;
    let it = tols.iter().position(|t| t.to_bits() == p.tol.to_bits())?;
    let ib = backends.iter().position(|b| b.name() == p.backend)?;
    Some(1 + (ih * tols.len() + it) * backends.len() + ib)
}

/// The VTU file of point `p` (from 1) of a plan of `total` points, inside [`SOLUTIONS_DIR`]:
/// `<p>_h<hmax>_<backend>_tol<tol>.vtu`, `p` zero-padded to the width of `total`, a `/` in the
/// backend's name (`clarabel/dual`) written `-`.
pub fn solution_file_name(p: usize, total: usize, hmax: f64, backend: &str, tol: f64) -> String {
    let width = total.max(1).to_string().len();
    format!(
        "{p:0width$}_h{hmax}_{}_tol{tol:e}.vtu",
        backend.replace(['/', '\\'], "-")
    )
}

/// Writes the PVD collection: one `DataSet` per `(timestep, file, label)`.
pub(crate) fn write_pvd(
    w: &mut dyn std::io::Write,
    entries: &[(usize, String, String)],
) -> std::io::Result<()> {
    use crate::output::xml_escape;
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">"
    )?;
    writeln!(w, "  <Collection>")?;
    for (step, file, label) in entries {
        // Labels are built from numbers and backend names: no "--" can occur in them.
        writeln!(w, "    <!-- {} -->", label.replace("--", "- -"))?;
        writeln!(
            w,
            "    <DataSet timestep=\"{step}\" group=\"\" part=\"0\" file=\"{}\"/>",
            xml_escape(file)
        )?;
    }
    writeln!(w, "  </Collection>")?;
    writeln!(w, "</VTKFile>")
}

/// The collection's entries: every point of `points` whose VTU exists under `dir`, in plan
/// order.
fn pvd_entries(
    dir: &Path,
    grid: &(Vec<f64>, Vec<f64>, Vec<BackendKind>),
    total: usize,
    points: &[Point],
) -> Vec<(usize, String, String)> {
    let mut entries: Vec<(usize, String, String)> = points
        .iter()
        .filter_map(|pt| {
            let p = plan_index(grid, pt)?;
            let name = solution_file_name(p, total, pt.hmax, &pt.backend, pt.tol);
            dir.join(SOLUTIONS_DIR).join(&name).is_file().then(|| {
                (
                    p,
                    format!("{SOLUTIONS_DIR}/{name}"),
                    format!(
                        "point {p}: hmax {}, {}, tol {:e}, {}",
                        pt.hmax, pt.backend, pt.tol, pt.status
                    ),
                )
            })
        })
        .collect();
    entries.sort_by_key(|e| e.0);
    entries
}

/// `max |u − u_ref| / max |u_ref|` over the nodes: the `error_vs_reference` column.
pub(crate) fn error_vs(u_ref: &[f64], u: &[f64]) -> f64 {
    let scale = max_displacement(u_ref).max(f64::MIN_POSITIVE);
    u_ref
        .chunks(2)
        .zip(u.chunks(2))
        .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
        .fold(0.0, f64::max)
        / scale
}

/// Whether a solved point at the tightest tolerance with worst residual `worst` becomes its
/// mesh's reference, replacing `current` (the reference so far, in plan order).
pub(crate) fn better_reference(current: Option<f64>, worst: f64) -> bool {
    current.is_none_or(|r| worst < r)
}

/// Runs the sweep into `dir/sweep.csv` and its plots (see the [module docs](self) for the
/// files).  Plot headings use the part of the scene title before any colon.
///
/// `progress(done, total, what)` is called when a mesh starts (meshing, the floor), when each
/// point starts (`what` names it, ending in `: solving`) and when it ends (`done` counts the
/// finished points of this run's share of the plan, `total` is that share).
///
/// With `plan.shard`, only that shard's points run (see [`shard`]): the error columns are left
/// empty, `shard.json` and `displacements/` are written for `sweep merge`.  With `plan.vtu`,
/// every point run writes `solutions/<point>.vtu` and the set gets [`SOLUTIONS_FILE`].
///
/// Points whose backend fails (any status other than `solved`) are written like the others and
/// counted in [`SweepOutcome::failed`]; an error that stops a whole mesh (meshing, assembly, a
/// scene without contact rows) ends the sweep with an error, keeping the points written so far.
pub fn sweep(
    scene: &Scene,
    plan: &SweepPlan,
    options: &SolveOptions,
    limits: &MeshLimits,
    dir: &Path,
    mut progress: impl FnMut(usize, usize, &str),
) -> Result<SweepOutcome, SweepError> {
    validate_plan(scene, plan, limits)?;
    let hash = scene_hash(scene, &plan.bodies);
    let csv_path = dir.join(SWEEP_FILE);
    // Read-only checks first, so that a refusal does not even create the directory.
    if csv_path.exists() && !plan.resume && !plan.overwrite {
        return Err(SweepError::Exists(csv_path));
    }
    let lock = DirLock::acquire(dir)?;
    let exists = std::fs::symlink_metadata(&csv_path).is_ok();
    if exists && !plan.resume && !plan.overwrite {
        return Err(SweepError::Exists(csv_path));
    }
    let mut points = if plan.resume && exists {
        read_for_resume(&csv_path, &hash, plan)?
    } else {
        Vec::new()
    };
    let done: HashSet<String> = points
        .iter()
        .map(|p| key(p.hmax, &p.backend, p.tol))
        .collect();
    let the_grid = grid(plan);
    let (hmaxes, tols, backends) = &the_grid;
    let per_mesh = tols.len() * backends.len();
    let plan_total = hmaxes.len() * per_mesh;
    let owns = |p: usize| plan.shard.is_none_or(|s| s.owns(p));
    let total = (1..=plan_total).filter(|&p| owns(p)).count();
    let mut manifest = plan.shard.map(|shard| Manifest {
        format: shard::MANIFEST_FORMAT.to_string(),
        version: env!("CARGO_PKG_VERSION").to_string(),
        title: scene.title.clone(),
        scene_hash: hash.clone(),
        bodies: plan.bodies.clone(),
        hmax: hmaxes.clone(),
        backends: backends.iter().map(|b| b.name().to_string()).collect(),
        tols: tols.clone(),
        repeat: Some(plan.repeat),
        time_limit_s: plan.time_limit.map(|t| t.as_secs_f64()),
        shard,
        points: plan_total,
        complete: false,
        skipped: Vec::new(),
    });
    let displacements = plan
        .shard
        .map(|_| DirLock::acquire(&dir.join(shard::DISPLACEMENTS_DIR)))
        .transpose()?;
    let solutions = plan
        .vtu
        .then(|| DirLock::acquire(&dir.join(SOLUTIONS_DIR)))
        .transpose()?;
    let mut count = 0;
    let mut given_up: HashSet<BackendKind> = HashSet::new();
    let repeat = plan.repeat;

    for (ih, &h) in hmaxes.iter().enumerate() {
        let index = |it: usize, ib: usize| 1 + (ih * tols.len() + it) * backends.len() + ib;
        let mine: Vec<(usize, usize)> = (0..tols.len())
            .flat_map(|it| (0..backends.len()).map(move |ib| (it, ib)))
            .filter(|&(it, ib)| owns(index(it, ib)))
            .collect();
        let todo = mine
            .iter()
            .filter(|&&(it, ib)| !done.contains(&key(h, backends[ib].name(), tols[it])))
            .count();
        if todo == 0 {
            count += mine.len();
            if !mine.is_empty() {
                progress(count, total, &format!("hmax {h}: already done"));
            }
            continue;
        }
        progress(count, total, &format!("hmax {h}: meshing and assembling"));
        let s = with_hmax(scene, &plan.bodies, h);
        let mut mesh_times = Vec::with_capacity(repeat);
        let mut assemble_times = Vec::with_capacity(repeat);
        let mut prepared = None;
        for _ in 0..repeat {
            let p = run::prepare(&s, limits)?;
            mesh_times.push(p.mesh_s);
            assemble_times.push(p.assemble_s);
            prepared = Some(p);
        }
        let Some(prepared) = prepared else {
            continue;
        };
        if prepared.model.rows() == 0 {
            return Err(RunError::NoContact(format!("the mesh at hmax {h}")).into());
        }
        progress(
            count,
            total,
            &format!(
                "hmax {h}: timing the floor ({} DOFs)",
                prepared.model.free.len()
            ),
        );
        let qp = solve::ScaledQp::new(prepared.qp);
        let model = &prepared.model;
        // One untimed factorisation first: the first touch of a large factor's memory costs page
        // faults that later solves (the backends') do not pay; timing it cold inflated the floor
        // twofold at 10⁶ DOFs.
        let floor_info = solve::floor(&qp.problem)
            .map_err(|e| RunError::from(solve::SolveError::from(e)))?
            .info;
        let floors: Vec<f64> = (0..repeat)
            .map(|_| solve::floor_time(&qp.problem).map(|d| d.as_secs_f64()))
            .collect::<Result<_, _>>()
            .map_err(|e| RunError::from(solve::SolveError::from(e)))?;
        let (mesh_s, assemble_s, floor_s) =
            (median(mesh_times), median(assemble_times), median(floors));

        let mut reference: Option<(f64, Vec<f64>)> = None; // (residual, displacement)
        for &(it, ib) in &mine {
            let (t, kind, p) = (tols[it], backends[ib], index(it, ib));
            let label = format!("hmax {h} {} tol {t:e}", kind.name());
            let skip_row = done.contains(&key(h, kind.name(), t));
            // The tightest tolerance is always solved (again, if resuming) to fix the reference;
            // a shard leaves the reference to `sweep merge`.
            let needed_for_reference = plan.shard.is_none() && it == 0 && reference.is_none();
            if (skip_row && !needed_for_reference) || given_up.contains(&kind) {
                count += 1;
                let why = if skip_row {
                    "already done"
                } else {
                    "skipped (time limit on a coarser mesh)"
                };
                progress(count, total, &format!("{label}: {why}"));
                continue;
            }
            progress(count, total, &format!("{label}: solving"));
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
            let worst = sol.residuals.worst();
            if it == 0
                && sol.status == QpStatus::Solved
                && better_reference(reference.as_ref().map(|r| r.0), worst)
            {
                reference = Some((worst, sol.displacement.clone()));
            }
            count += 1;
            progress(count, total, &format!("{label}: {}", sol.status.as_str()));
            if skip_row {
                continue;
            }
            let error_vs_reference = if plan.shard.is_some() {
                None
            } else {
                reference
                    .as_ref()
                    .map(|(_, u_ref)| error_vs(u_ref, &sol.displacement))
            };
            let solve_s = median(times);
            let point = Point {
                hmax: h,
                dofs: model.free.len(),
                constraints: model.rows(),
                backend: kind.name().to_string(),
                tol: t,
                status: sol.status.as_str().to_string(),
                backend_status: sol.backend_status.as_str().to_string(),
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
                scene_hash: hash.clone(),
                floor_ordering: floor_info.ordering.as_str().to_string(),
                floor_nnz_l: floor_info.nnz_l,
            };
            // The point's own files first, so that every row of sweep.csv has its files.
            if let Some(dlock) = &displacements {
                let name = shard::point_data_name(p);
                let mut set = OutputSet::new(dlock, Some(&name), &[&name])?;
                set.write(&name, |w| {
                    shard::write_point_data(w, worst, &sol.displacement)
                })?;
                set.commit()?;
            }
            if let Some(slock) = &solutions {
                write_solution(
                    slock,
                    &s,
                    model,
                    &sol,
                    &solution_file_name(p, plan_total, h, kind.name(), t),
                )?;
            }
            points.push(point);
            checkpoint(&lock, &points, manifest.as_ref())?;
        }
    }
    if plan.shard.is_none() {
        fill_error_vs_finest(&mut points);
    }
    let rows: Vec<crate::plots::SweepRow> = points.iter().map(Point::to_row).collect();
    // Plot titles get the part of the scene title before any colon, to stay on one line.
    let short = scene.title.split(':').next().unwrap_or(&scene.title).trim();
    let plots = crate::plots::render_sweep(&rows, short)?;
    let mut set = OutputSet::new(&lock, Some(SWEEP_FILE), &sweep_members())?;
    let csv = set.write(SWEEP_FILE, |w| write_csv(w, &points))?;
    let mut plot_paths = Vec::new();
    for (name, svg) in &plots {
        plot_paths.push(set.write(name, |w| w.write_all(svg.as_bytes()))?);
    }
    let mut files = Vec::new();
    if let Some(m) = &mut manifest {
        let present: HashSet<usize> = points
            .iter()
            .filter_map(|pt| plan_index(&the_grid, pt))
            .collect();
        m.skipped = m
            .shard
            .points(plan_total)
            .into_iter()
            .filter(|p| !present.contains(p))
            .collect();
        m.complete = true;
        files.push(set.write(shard::MANIFEST_FILE, |w| m.write(w))?);
    }
    if plan.vtu {
        let entries = pvd_entries(dir, &the_grid, plan_total, &points);
        files.push(set.write(SOLUTIONS_FILE, |w| write_pvd(w, &entries))?);
    }
    set.commit()?;
    let failed = points.iter().filter(|p| p.status != "solved").count();
    Ok(SweepOutcome {
        csv,
        plots: plot_paths,
        skipped: total.saturating_sub(points.len()),
        failed,
        points,
        scene_hash: hash,
        files,
    })
}

/// Writes one point's solution as `name` into the locked `solutions/` directory (its own
/// output set: complete or absent).
fn write_solution(
    lock: &DirLock,
    scene: &Scene,
    model: &signorini_core::model::Model,
    sol: &Solution,
    name: &str,
) -> Result<(), OutputError> {
    let fields = signorini_core::report::body_fields(model, sol);
    let bodies = crate::output::BodyField::of_bodies(&model.meshes, &fields, &scene.bodies);
    crate::output::check_fields(&bodies)?;
    let mut set = OutputSet::new(lock, Some(name), &[name])?;
    set.write(name, |w| crate::output::write_vtu_to(w, &bodies))?;
    set.commit().map(drop)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a64_matches_the_published_test_vectors() {
        // From the FNV reference test suite (Fowler, Noll, Vo: test vectors for FNV-1a 64).
        assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn scene_hash_ignores_swept_hmax_and_title_but_nothing_else() {
        let scene = run::load_scene(None).unwrap();
        let all: Vec<String> = Vec::new();
        let upper = vec!["upper".to_string()];
        let h = scene_hash(&scene, &all);
        assert_eq!(h.len(), 16);
        assert!(h.chars().all(|c| c.is_ascii_hexdigit()));
        // Independent of the swept sizes and of the title.
        assert_eq!(scene_hash(&with_hmax(&scene, &all, 0.01), &all), h);
        let hu = scene_hash(&scene, &upper);
        assert_eq!(scene_hash(&with_hmax(&scene, &upper, 0.05), &upper), hu);
        let mut retitled = scene.clone();
        retitled.title = "another title".into();
        assert_eq!(scene_hash(&retitled, &all), h);
        // Which bodies are swept, a size that is not swept, and the physics all count.
        assert_ne!(hu, h);
        let mut lower_finer = scene.clone();
        lower_finer.bodies[1].hmax = 0.1;
        assert_ne!(scene_hash(&lower_finer, &upper), hu);
        let mut stiffer = scene.clone();
        // The next float up: the smallest possible change.
        stiffer.bodies[0].young = f64::from_bits(scene.bodies[0].young.to_bits() + 1);
        assert_ne!(scene_hash(&stiffer, &all), h);
        let mut loaded = scene.clone();
        loaded.neumann[0].traction.coefficients[1][2] *= 2.0;
        assert_ne!(scene_hash(&loaded, &all), h);
        let mut renamed = scene.clone();
        renamed.probes[0].name.push('x');
        assert_ne!(scene_hash(&renamed, &all), h);
    }

    /// The progress callback names a point when it starts, not only once it is done: the bar
    /// used to show the previous point's label (and no sign of life) while a point ran.
    #[test]
    fn progress_names_each_point_before_it_runs() {
        let scene = run::load_scene(None).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let plan = SweepPlan {
            hmax: vec![0.3, 0.2],
            bodies: Vec::new(),
            backends: vec![BackendKind::Clarabel, BackendKind::DualPgs],
            tols: vec![1e-9],
            repeat: 1,
            time_limit: None,
            resume: false,
            overwrite: false,
            shard: Some(Shard { index: 2, count: 3 }),
            vtu: false,
        };
        let mut calls: Vec<(usize, usize, String)> = Vec::new();
        sweep(
            &scene,
            &plan,
            &SolveOptions::default(),
            &MeshLimits::default(),
            dir.path(),
            |d, t, w| calls.push((d, t, w.to_string())),
        )
        .unwrap();
        // Shard 2/3 of 4 points runs point 2 alone: hmax 0.3, dual-pgs.
        let texts: Vec<&str> = calls.iter().map(|c| c.2.as_str()).collect();
        assert_eq!(
            texts,
            [
                "hmax 0.3: meshing and assembling",
                "hmax 0.3: timing the floor (236 DOFs)",
                "hmax 0.3 dual-pgs tol 1e-9: solving",
                "hmax 0.3 dual-pgs tol 1e-9: solved",
            ]
        );
        let counts: Vec<(usize, usize)> = calls.iter().map(|c| (c.0, c.1)).collect();
        assert_eq!(counts, [(0, 1), (0, 1), (0, 1), (1, 1)]);
    }

    #[test]
    fn the_header_is_the_points_fields() {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.serialize(Point {
            hmax: 0.1,
            dofs: 1,
            constraints: 1,
            backend: "b".into(),
            tol: 1e-9,
            status: "solved".into(),
            backend_status: "solved".into(),
            iterations: 1,
            mesh_s: 0.0,
            assemble_s: 0.0,
            solve_s: 0.0,
            floor_s: 0.0,
            ratio_to_floor: 0.0,
            error_vs_reference: None,
            error_vs_finest: None,
            max_displacement: 0.0,
            peak_rss_mb: 0.0,
            max_penetration: 0.0,
            stationarity: 0.0,
            complementarity: 0.0,
            probes: String::new(),
            scene_hash: String::new(),
            floor_ordering: "amd".into(),
            floor_nnz_l: 1,
        })
        .unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        assert_eq!(text.lines().next().unwrap(), COLUMNS.join(","));
    }
}
