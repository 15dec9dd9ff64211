//! `signorini sweep merge DIR…`: the shards of one sweep joined into one `sweep.csv` and its
//! plots.
//!
//! Every check runs before anything is written; the first violation is refused with
//! [`MergeError::Refused`] naming the file (and the line, where there is one):
//!
//! * each DIR holds `shard.json` (a [`Manifest`]) of format [`super::shard::MANIFEST_FORMAT`],
//!   marked `complete` (an interrupted shard is finished with `--resume` first);
//! * every manifest names the same study as the first DIR's: scene hash, swept bodies, hmax
//!   grid, backends, tolerances, number of shards N and number of points;
//! * every shard `I` of `1..=N` is given exactly once (a duplicate names both directories, a
//!   missing one is named);
//! * each shard's `sweep.csv` is read as strictly as `--resume` reads one (header, line breaks,
//!   complete rows, the study's scene hash, no point twice, across all shards), every row is a
//!   point of the grid that belongs to that shard, and every point of the shard is there
//!   unless the manifest lists it as skipped after a time limit;
//! * every row has its `displacements/<p>.u` file, readable, with as many values as the other
//!   points of the same mesh.
//!
//! The merged rows are written in plan order.  When shards were run with `--vtu`, their
//! `solutions/<point>.vtu` files are copied into `OUT/solutions/` and `OUT/solutions.pvd` lists
//! them (timestep = the point's number in the plan), so the merged directory stands on its own.
//!  The error columns, left empty by the shards, are
//! computed here as an unsharded sweep computes them: `error_vs_reference` against the mesh's
//! reference (walking the mesh's points in plan order, the solved point at the tightest
//! tolerance with the smallest worst residual so far, from the stored displacements and
//! residuals), `error_vs_finest` by [`super::fill_error_vs_finest`] over all merged points.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::shard::{self, Manifest, Shard};
use super::{
    better_reference, error_vs, fill_error_vs_finest, key, solution_file_name, sweep_members,
    write_csv, write_pvd, Point, SOLUTIONS_DIR, SOLUTIONS_FILE, SWEEP_FILE,
};
use crate::outdir::{DirLock, OutputSet};
use crate::output::OutputError;

/// Why a merge refused or failed.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    /// An input is not a shard of the study, is incomplete or damaged.
    #[error("cannot merge: {}{}: {reason}", path.display(), line.map_or(String::new(), |l| format!(": line {l}")))]
    Refused {
        /// The offending file (or directory).
        path: PathBuf,
        /// 1-based line of the file, when the fault has one.
        line: Option<u64>,
        /// What is wrong.
        reason: String,
    },
    /// The merged `sweep.csv` exists and `overwrite` was not asked for.
    #[error("{} already exists: pass --overwrite to replace it", .0.display())]
    Exists(PathBuf),
    /// Writing the merged set failed.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// What a merge wrote.
#[derive(Debug, Clone)]
pub struct MergeOutcome {
    /// `out/sweep.csv`.
    pub csv: PathBuf,
    /// The plots written.
    pub plots: Vec<PathBuf>,
    /// `solutions.pvd`, when some shard wrote its points' solutions (`--vtu`).
    pub files: Vec<PathBuf>,
    /// The merged points, in plan order.
    pub points: Vec<Point>,
    /// The study's manifest (of the first shard, with the shard set to `1/1`).
    pub manifest: Manifest,
    /// Points of the plan that no shard ran (skipped after a time limit).
    pub skipped: usize,
    /// Points whose status is not `solved`.
    pub failed: usize,
}

fn refused(path: &Path, line: Option<u64>, reason: impl Into<String>) -> MergeError {
    MergeError::Refused {
        path: path.to_path_buf(),
        line,
        reason: reason.into(),
    }
}

/// The line (from 1) of `"key":` in a pretty JSON text, if any.
fn line_of(text: &str, key: &str) -> Option<u64> {
    let needle = format!("\"{key}\":");
    text.lines()
        .position(|l| l.trim_start().starts_with(&needle))
        .map(|i| i as u64 + 1)
}

/// Reads and checks `dir/shard.json`.
fn read_manifest(dir: &Path) -> Result<(PathBuf, String, Manifest), MergeError> {
    let path = dir.join(shard::MANIFEST_FILE);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        refused(
            &path,
            None,
            format!("{e}: not the output of `signorini sweep --shard I/N`"),
        )
    })?;
    let m: Manifest = serde_json::from_str(&text).map_err(|e| {
        refused(
            &path,
            Some(e.line() as u64),
            format!("not a shard manifest: {e}"),
        )
    })?;
    if m.format != shard::MANIFEST_FORMAT {
        return Err(refused(
            &path,
            line_of(&text, "format"),
            format!(
                "format \"{}\", expected \"{}\"",
                m.format,
                shard::MANIFEST_FORMAT
            ),
        ));
    }
    if m.shard.index == 0 || m.shard.index > m.shard.count {
        return Err(refused(
            &path,
            line_of(&text, "shard"),
            format!("shard {} is not I/N with 1 ≤ I ≤ N", m.shard),
        ));
    }
    if m.points != m.hmax.len() * m.tols.len() * m.backends.len() {
        return Err(refused(
            &path,
            line_of(&text, "points"),
            format!(
                "{} points, but the grid has {}",
                m.points,
                m.hmax.len() * m.tols.len() * m.backends.len()
            ),
        ));
    }
    if !m.complete {
        return Err(refused(
            &path,
            line_of(&text, "complete"),
            format!(
                "shard {} did not finish (interrupted?): run it again with --resume first",
                m.shard
            ),
        ));
    }
    Ok((path, text, m))
}

/// Compares the study of `m` (read from `path`, `text`) with the first shard's.
fn same_study(
    first: &(PathBuf, Manifest),
    path: &Path,
    text: &str,
    m: &Manifest,
) -> Result<(), MergeError> {
    let (fp, f) = first;
    let differ = |field: &str, what: String| {
        refused(
            path,
            line_of(text, field),
            format!(
                "{what} differs from {}: the shards are not of the same sweep",
                fp.display()
            ),
        )
    };
    if m.scene_hash != f.scene_hash {
        return Err(differ(
            "scene_hash",
            format!("scene_hash {} (vs {})", m.scene_hash, f.scene_hash),
        ));
    }
    if m.bodies != f.bodies {
        return Err(differ(
            "bodies",
            format!("the swept bodies {:?} (vs {:?})", m.bodies, f.bodies),
        ));
    }
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    if bits(&m.hmax) != bits(&f.hmax) {
        return Err(differ(
            "hmax",
            format!("the hmax grid {:?} (vs {:?})", m.hmax, f.hmax),
        ));
    }
    if m.backends != f.backends {
        return Err(differ(
            "backends",
            format!("the backends {:?} (vs {:?})", m.backends, f.backends),
        ));
    }
    if bits(&m.tols) != bits(&f.tols) {
        return Err(differ(
            "tols",
            format!("the tolerances {:?} (vs {:?})", m.tols, f.tols),
        ));
    }
    // Times measured with other repeats or another limit (which decides which backends are
    // skipped on finer meshes) are not one sweep's.
    let shown = |x: Option<String>| x.unwrap_or_else(|| "unrecorded".to_string());
    if m.repeat != f.repeat {
        return Err(differ(
            "repeat",
            format!(
                "--repeat {} (vs {})",
                shown(m.repeat.map(|r| r.to_string())),
                shown(f.repeat.map(|r| r.to_string()))
            ),
        ));
    }
    if m.time_limit_s.map(f64::to_bits) != f.time_limit_s.map(f64::to_bits) {
        let limit = |t: Option<f64>| t.map_or("none".to_string(), |t| format!("{t} s"));
        return Err(differ(
            "time_limit_s",
            format!(
                "--time-limit {} (vs {})",
                limit(m.time_limit_s),
                limit(f.time_limit_s)
            ),
        ));
    }
    if m.shard.count != f.shard.count {
        return Err(differ(
            "shard",
            format!(
                "the number of shards {} (vs {})",
                m.shard.count, f.shard.count
            ),
        ));
    }
    Ok(())
}

/// The number (from 1) of a row's point in the manifest's plan.
fn plan_point(m: &Manifest, p: &Point) -> Option<usize> {
    let ih = m
        .hmax
        .iter()
        .position(|h| h.to_bits() == p.hmax.to_bits())?;
    let it = m.tols.iter().position(|t| t.to_bits() == p.tol.to_bits())?;
    let ib = m.backends.iter().position(|b| *b == p.backend)?;
    Some(1 + (ih * m.tols.len() + it) * m.backends.len() + ib)
}

/// Reads a shard's `sweep.csv` strictly (see [`super::read_rows_strict`]); returns `(line, point)`
/// pairs.
fn read_rows(path: &Path) -> Result<Vec<(u64, Point)>, MergeError> {
    let bytes = std::fs::read(path).map_err(|e| refused(path, None, e.to_string()))?;
    let mut rows = Vec::new();
    super::read_rows_strict(
        bytes,
        |line, reason| refused(path, Some(line), reason),
        |line, p| {
            rows.push((line, p));
            Ok(())
        },
    )?;
    Ok(rows)
}

/// Checks the shards in `dirs` (see the [module docs](self)) and writes their merged
/// `sweep.csv` and plots into `out` (refused if `out/sweep.csv` exists, unless `overwrite`).
/// On any refusal nothing is written.
pub fn merge(dirs: &[PathBuf], out: &Path, overwrite: bool) -> Result<MergeOutcome, MergeError> {
    let Some(first_dir) = dirs.first() else {
        return Err(refused(Path::new("."), None, "no shard directory given"));
    };
    let manifests = read_manifests(dirs)?;
    let study = manifests[0].1.clone();
    check_every_shard(&manifests, study.shard.count)?;
    let (mut rows, row_dirs) = read_shards(dirs, &manifests, &study)?;
    rows.sort_by_key(|r| r.0);
    let sources: Vec<(usize, Point, PathBuf)> = rows
        .iter()
        .map(|(k, p, _, _)| (*k, p.clone(), row_dirs[k].clone()))
        .collect();
    let points_index: HashMap<usize, usize> =
        rows.iter().enumerate().map(|(i, r)| (r.0, i)).collect();
    let mut points = with_error_vs_reference(&rows, &row_dirs, &study)?;
    fill_error_vs_finest(&mut points);
    // Everything checked: write.
    let csv_path = out.join(SWEEP_FILE);
    if csv_path.exists() && !overwrite {
        return Err(MergeError::Exists(csv_path));
    }
    for dir in dirs {
        if same_dir(dir, out) {
            return Err(refused(
                dir,
                None,
                "is both a shard and the output directory: merge into another directory (--out)",
            ));
        }
    }
    let _ = first_dir;
    let rows_for_plots: Vec<crate::plots::SweepRow> = points.iter().map(Point::to_row).collect();
    let short = study.title.split(':').next().unwrap_or(&study.title).trim();
    let plots = crate::plots::render_sweep(&rows_for_plots, short)?;
    let lock = DirLock::acquire(out)?;
    if std::fs::symlink_metadata(&csv_path).is_ok() && !overwrite {
        return Err(MergeError::Exists(csv_path));
    }
    let solutions = copy_solutions(&sources, study.points, out)?;
    let (csv, plot_paths, files) = write_merged(&lock, &points, &points_index, &plots, &solutions)?;
    let failed = points.iter().filter(|p| p.status != "solved").count();
    let manifest = merged_manifest(study, &manifests);
    let skipped = manifest.skipped.len();
    Ok(MergeOutcome {
        csv,
        plots: plot_paths,
        files,
        points,
        manifest,
        skipped,
        failed,
    })
}

/// A merged row: its number in the plan, the point, its worst residual and its displacements.
type Row = (usize, Point, f64, Vec<f64>);

/// The manifests of `dirs`, in order, checked to describe one study with each shard once.
fn read_manifests(dirs: &[PathBuf]) -> Result<Vec<(PathBuf, Manifest)>, MergeError> {
    let mut manifests: Vec<(PathBuf, Manifest)> = Vec::with_capacity(dirs.len());
    for dir in dirs {
        let (path, text, m) = read_manifest(dir)?;
        if let Some(first) = manifests.first() {
            same_study(first, &path, &text, &m)?;
        }
        if let Some((other, _)) = manifests
            .iter()
            .find(|(_, o)| o.shard.index == m.shard.index)
        {
            return Err(refused(
                &path,
                line_of(&text, "shard"),
                format!(
                    "shard {} is given twice (also as {})",
                    m.shard,
                    other.display()
                ),
            ));
        }
        manifests.push((path, m));
    }
    Ok(manifests)
}

/// Refuses a set of manifests that lacks one of the `count` shards.
fn check_every_shard(manifests: &[(PathBuf, Manifest)], count: usize) -> Result<(), MergeError> {
    let missing: Vec<String> = (1..=count)
        .filter(|i| !manifests.iter().any(|(_, m)| m.shard.index == *i))
        .map(|i| format!("{i}/{count}"))
        .collect();
    if !missing.is_empty() {
        return Err(refused(
            &manifests[0].0,
            line_of(
                &std::fs::read_to_string(&manifests[0].0).unwrap_or_default(),
                "shard",
            ),
            format!(
                "the sweep has {count} shards, but shard(s) {} are not among the directories given",
                missing.join(", ")
            ),
        ));
    }
    Ok(())
}

/// The rows of every shard with their displacements, and the directory of each point; every row
/// checked to be the study's, its shard's and given once, every point of a shard present or
/// listed as skipped.
fn read_shards(
    dirs: &[PathBuf],
    manifests: &[(PathBuf, Manifest)],
    study: &Manifest,
) -> Result<(Vec<Row>, HashMap<usize, PathBuf>), MergeError> {
    let mut seen: HashMap<String, (PathBuf, u64)> = HashMap::new();
    let mut rows: Vec<Row> = Vec::with_capacity(study.points);
    let mut row_dirs: HashMap<usize, PathBuf> = HashMap::new();
    for (dir, (mpath, m)) in dirs.iter().zip(manifests) {
        let csv = dir.join(SWEEP_FILE);
        let mut present = Vec::new();
        for (line, p) in read_rows(&csv)? {
            let k = check_row(&csv, line, &p, m, study, &mut seen)?;
            let upath = dir
                .join(shard::DISPLACEMENTS_DIR)
                .join(shard::point_data_name(k));
            let (worst, u) = shard::read_point_data(&upath).map_err(|e| {
                refused(
                    &upath,
                    None,
                    format!(
                        "the displacements of point {k} ({} line {line}): {e}",
                        csv.display()
                    ),
                )
            })?;
            present.push(k);
            row_dirs.insert(k, dir.clone());
            rows.push((k, p, worst, u));
        }
        for k in m.shard.points(study.points) {
            if !present.contains(&k) && !m.skipped.contains(&k) {
                return Err(refused(
                    &csv,
                    None,
                    format!(
                        "point {k} of shard {} is neither in the file nor listed as skipped in {}",
                        m.shard,
                        mpath.display()
                    ),
                ));
            }
        }
    }
    Ok((rows, row_dirs))
}

/// Checks row `p` (line `line` of `csv`, a file of shard `m`): the study's scene, a point of
/// its grid, of this shard, not seen before (`seen`, updated).  Returns its number in the plan.
fn check_row(
    csv: &Path,
    line: u64,
    p: &Point,
    m: &Manifest,
    study: &Manifest,
    seen: &mut HashMap<String, (PathBuf, u64)>,
) -> Result<usize, MergeError> {
    let count = study.shard.count;
    if p.scene_hash != study.scene_hash {
        return Err(refused(
            csv,
            Some(line),
            format!(
                "scene_hash {} is not the study's {}: the row belongs to another scene",
                p.scene_hash, study.scene_hash
            ),
        ));
    }
    let Some(k) = plan_point(m, p) else {
        return Err(refused(
            csv,
            Some(line),
            format!(
                "hmax {}, {}, tol {:e} is not a point of the study's grid",
                p.hmax, p.backend, p.tol
            ),
        ));
    };
    if !m.shard.owns(k) {
        return Err(refused(
            csv,
            Some(line),
            format!(
                "point {k} belongs to shard {}/{count}, not to this directory's shard {}",
                Shard::of_point(k, count),
                m.shard
            ),
        ));
    }
    if let Some((f, l)) = seen.insert(key(p.hmax, &p.backend, p.tol), (csv.to_path_buf(), line)) {
        return Err(refused(
            csv,
            Some(line),
            format!(
                "repeats the point of {}: line {l} (hmax {}, {}, tol {:e})",
                f.display(),
                p.hmax,
                p.backend,
                p.tol
            ),
        ));
    }
    Ok(k)
}

/// The points of `rows` (in plan order) with `error_vs_reference`, mesh by mesh in plan order,
/// as an unsharded sweep computes it.
fn with_error_vs_reference(
    rows: &[Row],
    row_dirs: &HashMap<usize, PathBuf>,
    study: &Manifest,
) -> Result<Vec<Point>, MergeError> {
    let per_mesh = study.tols.len() * study.backends.len();
    let mut points = Vec::with_capacity(rows.len());
    let mut reference: Option<(usize, f64, usize)> = None; // (mesh, worst, row)
    for i in 0..rows.len() {
        let (k, ref p, worst, ref u) = rows[i];
        let mesh = (k - 1) / per_mesh;
        if reference.is_some_and(|r| r.0 != mesh) {
            reference = None;
        }
        let tightest = (k - 1) % per_mesh < study.backends.len();
        if tightest && p.status == "solved" && better_reference(reference.map(|r| r.1), worst) {
            reference = Some((mesh, worst, i));
        }
        let mut p = p.clone();
        p.error_vs_reference = match reference {
            Some((_, _, r)) => {
                let u_ref = &rows[r].3;
                if u_ref.len() != u.len() {
                    let file = row_dirs[&k]
                        .join(shard::DISPLACEMENTS_DIR)
                        .join(shard::point_data_name(k));
                    return Err(refused(
                        &file,
                        None,
                        format!(
                            "point {k} has {} displacement values, but the reference of its mesh (point {}) has {}",
                            u.len(),
                            rows[r].0,
                            u_ref.len()
                        ),
                    ));
                }
                Some(error_vs(u_ref, u))
            }
            None => None,
        };
        points.push(p);
    }
    Ok(points)
}

/// The shards' solutions (written with --vtu), copied into `out/solutions/` so that the merged
/// directory stands on its own: `(point, file name, source)` of each one copied.
fn copy_solutions(
    sources: &[(usize, Point, PathBuf)],
    plan_points: usize,
    out: &Path,
) -> Result<Vec<(usize, String, String)>, MergeError> {
    let mut solutions: Vec<(usize, String, String)> = Vec::new();
    for (k, p, dir) in sources {
        let name = solution_file_name(*k, plan_points, p.hmax, &p.backend, p.tol);
        let from = dir.join(SOLUTIONS_DIR).join(&name);
        if from.is_file() {
            solutions.push((*k, name, from.display().to_string()));
        }
    }
    if !solutions.is_empty() {
        let slock = DirLock::acquire(&out.join(SOLUTIONS_DIR))?;
        for (_, name, from) in &solutions {
            let mut sset = OutputSet::new(&slock, Some(name), &[name.as_str()])?;
            sset.write(name, |w| {
                let mut f = std::fs::File::open(from)?;
                std::io::copy(&mut f, w).map(drop)
            })?;
            sset.commit()?;
        }
    }
    Ok(solutions)
}

/// The paths a merge wrote: `sweep.csv`, the plots, and `solutions.pvd` (if any).
type Written = (PathBuf, Vec<PathBuf>, Vec<PathBuf>);

/// Writes the merged output set: the solutions' collection (when some were copied), `sweep.csv`
/// and the plots.
fn write_merged(
    lock: &DirLock,
    points: &[Point],
    points_index: &HashMap<usize, usize>,
    plots: &[(&'static str, String)],
    solutions: &[(usize, String, String)],
) -> Result<Written, MergeError> {
    let mut files = Vec::new();
    let mut set = OutputSet::new(lock, Some(SWEEP_FILE), &sweep_members())?;
    if !solutions.is_empty() {
        let entries: Vec<(usize, String, String)> = solutions
            .iter()
            .map(|(k, name, _)| {
                let p = &points[points_index[k]];
                (
                    *k,
                    format!("{SOLUTIONS_DIR}/{name}"),
                    format!(
                        "point {k}: hmax {}, {}, tol {:e}, {}",
                        p.hmax, p.backend, p.tol, p.status
                    ),
                )
            })
            .collect();
        files.push(set.write(SOLUTIONS_FILE, |w| write_pvd(w, &entries))?);
    }
    let csv = set.write(SWEEP_FILE, |w| write_csv(w, points))?;
    let mut plot_paths = Vec::new();
    for (name, svg) in plots {
        plot_paths.push(set.write(name, |w| w.write_all(svg.as_bytes()))?);
    }
    set.commit()?;
    Ok((csv, plot_paths, files))
}

/// The study's manifest for the merged set: the shards' skipped points, sorted, as shard `1/1`.
fn merged_manifest(study: Manifest, manifests: &[(PathBuf, Manifest)]) -> Manifest {
    let mut manifest = study;
    manifest.skipped = manifests
        .iter()
        .flat_map(|(_, m)| m.skipped.iter().copied())
        .collect();
    manifest.skipped.sort_unstable();
    manifest.shard = Shard { index: 1, count: 1 };
    manifest
}

/// Whether `a` and `b` name the same existing directory.
fn same_dir(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}
