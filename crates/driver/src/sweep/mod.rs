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
//!
//! # Where each part lives
//!
//! `plan.rs` (the plan, its grid and checks), `execute.rs` (the sweep itself), `rows.rs`
//! (`sweep.csv`'s rows, read and written), `resume.rs` (`--resume`), `hash.rs` (the scene
//! hash), `accuracy.rs` (the error columns), `measure.rs` (memory, medians), `set.rs` (the
//! output set and its checkpoint), `solutions.rs` (`--vtu`), `shard.rs` and `merge.rs` (shards
//! and `sweep merge`).

use std::path::PathBuf;

use crate::output::OutputError;
use crate::run::RunError;

mod accuracy;
mod execute;
mod hash;
mod measure;
pub mod merge;
mod plan;
mod resume;
mod rows;
mod set;
pub mod shard;
mod solutions;

pub use accuracy::fill_error_vs_finest;
pub(crate) use accuracy::{better_reference, error_vs};
pub use execute::sweep;
pub use hash::{canonical_scene_text, scene_hash};
pub use measure::peak_rss_mb;
pub(crate) use plan::key;
pub use plan::{validate_plan, with_hmax, SweepPlan};
pub use resume::read_for_resume;
pub use rows::{read_points, Point, COLUMNS};
pub(crate) use rows::{read_rows_strict, write_csv};
pub(crate) use set::sweep_members;
pub use solutions::solution_file_name;
pub(crate) use solutions::write_pvd;

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
