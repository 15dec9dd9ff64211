//! `signorini qpset`: scenes exported as a [qpbenchmark](https://github.com/qpsolvers/qpbenchmark)
//! test set, laid out as qpbenchmark's own sets are (`maros_meszaros_qpbenchmark`,
//! `mpc_qpbenchmark`): one data file per problem under `data/`, a Python module whose
//! `TestSet` subclass (title, description, `sparse_only`, the problems) loads them, an empty
//! `results/` for qpbenchmark's results, and a README and `metadata.json` saying what each
//! problem is, its reference answer and our residual definitions.  See docs/qp-benchmark.md.
//!
//! Each problem is `min ½xᵀPx + qᵀx  s.t.  Gx ≤ h` with P = A, q = −f, G = B, h = g: by default
//! the nondimensionalised QP our backends see ([`signorini_core::qp::QpScaling`]), with `raw`
//! the user's units; a Tresca scene's box rows go through
//! [`signorini_core::qp::AuxiliaryForm`] (one-sided rows only).  Coulomb scenes and load paths
//! are not one QP and are skipped with the reason.
//!
//! `data/NAME.npz` holds the CSC arrays `P_indptr`, `P_indices` (`<i4`), `P_data`, `P_shape`
//! (and the same for G), `q`, `h`, the reference answer of our `auto` backend (`solved` at the
//! set's tolerance; a scene it does not solve is skipped) `x_ref`, `z_ref` and `objective_ref`
//! (a scalar), plus `kernel` (k × n, the rigid-body modes of floating bodies) when A is
//! singular.

mod files;
mod npz;
mod problem;
mod read;
mod solve;
mod texts;

use std::path::{Path, PathBuf};

pub use files::{write_set, SetOptions, SetSummary};
pub use npz::{read_npz, write_npz, NpyArray, NpyData, NpyValues};
pub use problem::{build, csc, refined, Built, ContactQp, ProblemKind, Reference};
pub use read::{read_problem, SetProblem};
pub use solve::{qpsolvers_residuals, run_set, set_files, settings_eps_abs, RunRow, TOL_FLOOR};
pub use texts::{MODULE_FILE, TEST_SET_CLASS};

/// Why a set could not be written (a scene that fails is reported and skipped, not this).
#[derive(Debug, thiserror::Error)]
pub enum QpsetError {
    /// A directory to read does not exist or cannot be listed.
    #[error("cannot read scene directory {}: {reason}", path.display())]
    Dir {
        /// The directory.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// The given directories hold no scene file.
    #[error("no scene file (*.toml) under {0}")]
    NoScenes(String),
    /// The output exists and is not empty, and `--force` was not given.
    #[error("{} exists and is not empty; pass --force to replace it", .0.display())]
    Exists(PathBuf),
    /// No scene gave a problem.
    #[error("no scene gave a QP: nothing to write")]
    Empty,
    /// One scene failed to load, mesh, assemble or solve.
    #[error("{}: {reason}", path.display())]
    Scene {
        /// The scene file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// The auxiliary rewriting of box rows was refused.
    #[error("auxiliary form: {0}")]
    Auxiliary(String),
    /// Writing failed.
    #[error("cannot write {}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}

/// Every `*.toml` under each of `dirs` (recursively), sorted per directory; a directory that
/// does not exist is refused.
pub fn scene_files(dirs: &[PathBuf]) -> Result<Vec<PathBuf>, QpsetError> {
    let mut all = Vec::new();
    for dir in dirs {
        let mut found = Vec::new();
        walk(dir, &mut found)?;
        found.sort();
        all.extend(found);
    }
    if all.is_empty() {
        let names: Vec<String> = dirs.iter().map(|d| d.display().to_string()).collect();
        return Err(QpsetError::NoScenes(names.join(", ")));
    }
    Ok(all)
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), QpsetError> {
    let entries = std::fs::read_dir(dir).map_err(|e| QpsetError::Dir {
        path: dir.to_path_buf(),
        reason: e.to_string(),
    })?;
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            walk(&path, out)?;
        } else if path.extension().is_some_and(|e| e == "toml") {
            out.push(path);
        }
    }
    Ok(())
}

/// The problem's name: the scene file's directory and stem, `dir-stem` (qpbenchmark names a
/// problem by its data file), characters outside `[A-Za-z0-9._-]` replaced by `_`.
pub fn problem_name(path: &Path) -> String {
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned());
    let parent = path
        .parent()
        .and_then(Path::file_name)
        .map(|s| s.to_string_lossy().into_owned());
    let name = match (parent, stem) {
        (Some(p), Some(s)) => format!("{p}-{s}"),
        (None, Some(s)) => s,
        _ => "problem".into(),
    };
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-') {
                c
            } else {
                '_'
            }
        })
        .collect()
}
