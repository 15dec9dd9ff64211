//! Writing a set whole or not at all: every file goes into a temporary directory beside the
//! target, which is renamed into place at the end (an earlier set, replaced with `force`, is
//! moved aside first and put back if the rename fails).

use std::collections::{HashMap, HashSet};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use serde_json::{json, Value};
use signorini_core::mesh::MeshLimits;

use super::npz::{write_npz, NpyArray, NpyData};
use super::problem::{build, csc, Built, ContactQp};
use super::texts;
use super::{problem_name, QpsetError};

/// How a set is built.
#[derive(Debug, Clone)]
pub struct SetOptions {
    /// Export in the user's units instead of the nondimensionalised form.
    pub raw: bool,
    /// Tolerance of the reference solve.
    pub tol: f64,
    /// Mesh limits of every scene.
    pub limits: MeshLimits,
    /// Refine every scene to about this many unknowns (`--large`).
    pub large: Option<usize>,
    /// Replace an existing non-empty output.
    pub force: bool,
}

/// What a written set holds.
#[derive(Debug, Clone, Default)]
pub struct SetSummary {
    /// Problems written (names).
    pub written: Vec<String>,
    /// Scenes left out, and why (not one QP, no contact rows).
    pub skipped: Vec<(PathBuf, String)>,
    /// Scenes that failed to build, and why.
    pub failed: Vec<(PathBuf, String)>,
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> QpsetError + '_ {
    move |source| QpsetError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Whether `out` exists and holds anything.
fn occupied(out: &Path) -> bool {
    match std::fs::read_dir(out) {
        Ok(mut entries) => entries.next().is_some(),
        Err(_) => out.exists(),
    }
}

/// Builds every scene of `scenes` and writes the set to `out`; `progress` gets one line per scene.
pub fn write_set(
    scenes: &[PathBuf],
    out: &Path,
    options: &SetOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<SetSummary, QpsetError> {
    if occupied(out) && !options.force {
        return Err(QpsetError::Exists(out.to_path_buf()));
    }
    let parent = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&parent).map_err(io(&parent))?;
    let stage = tempfile::Builder::new()
        .prefix(".qpset-stage-")
        .tempdir_in(&parent)
        .map_err(io(&parent))?;
    let data = stage.path().join("data");
    std::fs::create_dir_all(&data).map_err(io(&data))?;
    let results = stage.path().join("results");
    std::fs::create_dir_all(&results).map_err(io(&results))?;
    let mut summary = SetSummary::default();
    let mut entries = Vec::new();
    let mut names = HashSet::new();
    let mut seen: HashMap<[u8; 32], String> = HashMap::new();
    for (k, path) in scenes.iter().enumerate() {
        let head = format!("[{}/{}] {}", k + 1, scenes.len(), path.display());
        match build(
            path,
            options.raw,
            options.tol,
            &options.limits,
            options.large,
        ) {
            Ok(Built::Problem(p)) => {
                let name = unique(problem_name(path), &mut names);
                let file = data.join(format!("{name}.npz"));
                write_problem(&file, &p)?;
                // The same QP from two scenes (a fixture repeated at another name) counts once.
                let digest = file_digest(&file)?;
                if let Some(first) = seen.get(&digest) {
                    std::fs::remove_file(&file).map_err(io(&file))?;
                    let why = format!("the same QP as {first}");
                    progress(&format!("{head}: skipped: {why}"));
                    summary.skipped.push((path.clone(), why));
                    continue;
                }
                seen.insert(digest, name.clone());
                progress(&line(&head, &name, &p));
                entries.push(entry(&name, path, &p));
                summary.written.push(name);
            }
            Ok(Built::Skipped(why)) => {
                progress(&format!("{head}: skipped: {why}"));
                summary.skipped.push((path.clone(), why));
            }
            Err(e) => {
                progress(&format!("{head}: failed: {e}"));
                summary.failed.push((path.clone(), e.to_string()));
            }
        }
    }
    if summary.written.is_empty() {
        return Err(QpsetError::Empty);
    }
    let put = |name: &str, text: &str| {
        let path = stage.path().join(name);
        std::fs::write(&path, text).map_err(io(&path))
    };
    put(texts::MODULE_FILE, &texts::module())?;
    put(
        "README.md",
        &texts::readme(options.raw, options.tol, &entries),
    )?;
    let meta = metadata(options, &entries, &summary);
    put(
        "metadata.json",
        &serde_json::to_string_pretty(&meta).unwrap_or_default(),
    )?;
    put("results/.gitignore", "*\n!.gitignore\n")?;
    swap(stage, out, &parent)?;
    Ok(summary)
}

/// SHA-256 of a written file.
fn file_digest(path: &Path) -> Result<[u8; 32], QpsetError> {
    use sha2::Digest;
    let bytes = std::fs::read(path).map_err(io(path))?;
    Ok(sha2::Sha256::digest(&bytes).into())
}

/// `name`, or `name-2`, `name-3`, … if taken.
fn unique(name: String, taken: &mut HashSet<String>) -> String {
    let mut candidate = name.clone();
    let mut k = 2;
    while !taken.insert(candidate.clone()) {
        candidate = format!("{name}-{k}");
        k += 1;
    }
    candidate
}

/// The progress line of a written problem.
fn line(head: &str, name: &str, p: &ContactQp) -> String {
    let r = &p.reference;
    let reference = format!(
        "reference {} in {:.3} s, objective {:.6e}",
        r.backend, r.solve_s, r.objective
    );
    format!(
        "{head}: {name}: n = {}, m = {}, {:?}, {reference}",
        p.problem.dofs(),
        p.problem.rows(),
        p.kind
    )
}

/// Moves the staged set to `out`: an empty `out` is removed first; a non-empty one (allowed by
/// the caller) is moved aside and deleted once the new set is in place, or put back.
fn swap(stage: tempfile::TempDir, out: &Path, parent: &Path) -> Result<(), QpsetError> {
    let old = tempfile::Builder::new()
        .prefix(".qpset-old-")
        .tempdir_in(parent)
        .map_err(io(parent))?;
    let aside = old.path().join("set");
    let moved = if out.is_dir() && !occupied(out) {
        std::fs::remove_dir(out).map_err(io(out))?;
        false
    } else if out.exists() || out.is_symlink() {
        std::fs::rename(out, &aside).map_err(io(out))?;
        true
    } else {
        false
    };
    if let Err(e) = std::fs::rename(stage.path(), out) {
        if moved {
            let _ = std::fs::rename(&aside, out);
        }
        return Err(QpsetError::Io {
            path: out.to_path_buf(),
            source: e,
        });
    }
    // The staging directory is now `out`: dropping `stage` would try to remove a path that no
    // longer exists, which it ignores; `old` takes the previous set with it.
    drop(stage);
    drop(old);
    Ok(())
}

fn to_i32(v: &[usize], path: &Path) -> Result<Vec<i32>, QpsetError> {
    v.iter()
        .map(|&k| i32::try_from(k))
        .collect::<Result<_, _>>()
        .map_err(|_| QpsetError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::other("an index beyond 2³¹: too large for <i4 indices"),
        })
}

/// `data/NAME.npz` of one problem.
fn write_problem(path: &Path, p: &ContactQp) -> Result<(), QpsetError> {
    let qp = &p.problem;
    let (n, m) = (qp.dofs(), qp.rows());
    let (pp, pi, pv) = csc(&qp.stiffness);
    let (gp, gi, gv) = csc(&qp.constraints);
    let (pp, pi, gp, gi) = (
        to_i32(&pp, path)?,
        to_i32(&pi, path)?,
        to_i32(&gp, path)?,
        to_i32(&gi, path)?,
    );
    let q: Vec<f64> = qp.load.iter().map(|f| -f).collect();
    let p_dims = [i32::try_from(n).unwrap_or(i32::MAX); 2];
    let g_dims = [
        i32::try_from(m).unwrap_or(i32::MAX),
        i32::try_from(n).unwrap_or(i32::MAX),
    ];
    let kernel: Vec<f64> = qp.kernel.iter().flatten().copied().collect();
    let mut arrays = vec![
        arr("P_indptr", NpyData::I32(&pp), vec![pp.len()]),
        arr("P_indices", NpyData::I32(&pi), vec![pi.len()]),
        arr("P_data", NpyData::F64(&pv), vec![pv.len()]),
        arr("P_shape", NpyData::I32(&p_dims), vec![2]),
        arr("q", NpyData::F64(&q), vec![n]),
        arr("G_indptr", NpyData::I32(&gp), vec![gp.len()]),
        arr("G_indices", NpyData::I32(&gi), vec![gi.len()]),
        arr("G_data", NpyData::F64(&gv), vec![gv.len()]),
        arr("G_shape", NpyData::I32(&g_dims), vec![2]),
        arr("h", NpyData::F64(&qp.gap), vec![m]),
    ];
    if !kernel.is_empty() {
        arrays.push(arr(
            "kernel",
            NpyData::F64(&kernel),
            vec![qp.kernel.len(), n],
        ));
    }
    let r = &p.reference;
    let objective = [r.objective];
    arrays.push(arr("x_ref", NpyData::F64(&r.x), vec![r.x.len()]));
    arrays.push(arr("z_ref", NpyData::F64(&r.z), vec![r.z.len()]));
    arrays.push(arr("objective_ref", NpyData::F64(&objective), vec![]));
    let file = std::fs::File::create(path).map_err(io(path))?;
    let mut w = write_npz(BufWriter::new(file), &arrays).map_err(io(path))?;
    w.flush().map_err(io(path))
}

fn arr<'a>(name: &'a str, data: NpyData<'a>, shape: Vec<usize>) -> NpyArray<'a> {
    NpyArray { name, data, shape }
}

/// One problem's entry of `metadata.json`.
fn entry(name: &str, scene: &Path, p: &ContactQp) -> Value {
    json!({
        "name": name,
        "file": format!("data/{name}.npz"),
        "scene": scene.display().to_string(),
        "title": p.title,
        "kind": p.kind,
        "n": p.problem.dofs(),
        "m": p.problem.rows(),
        "nnz_P": p.problem.stiffness.nnz(),
        "nnz_G": p.problem.constraints.nnz(),
        "contact_unknowns": p.original_size.0,
        "contact_rows": p.original_size.1,
        "singular_P": !p.problem.kernel.is_empty(),
        "units": {
            "stiffness": p.scaling.stiffness,
            "displacement": p.scaling.displacement,
            "applied": !p.raw,
        },
        "prepare_s": p.prepare_s,
        "reference": p.reference,
    })
}

/// `metadata.json`.
fn metadata(options: &SetOptions, entries: &[Value], summary: &SetSummary) -> Value {
    let listed = |v: &[(PathBuf, String)]| -> Vec<Value> {
        v.iter()
            .map(|(p, why)| json!({"scene": p.display().to_string(), "reason": why}))
            .collect()
    };
    json!({
        "generator": format!("signorini {}", env!("CARGO_PKG_VERSION")),
        "problem": "minimise 1/2 x'Px + q'x subject to Gx <= h",
        "form": if options.raw { "raw (user units)" } else { "nondimensionalised (what signorini's backends see)" },
        "large": options.large,
        "reference_backend": "auto",
        "reference_tolerance": options.tol,
        "residuals": texts::residual_definitions(),
        "problems": entries,
        "skipped": listed(&summary.skipped),
        "failed": listed(&summary.failed),
    })
}
