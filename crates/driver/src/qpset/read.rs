//! Reading a set's problem back: the `.npz` files [`super::write_set`] writes (read by
//! [`super::read_npz`]: `<f8` or `<i4` arrays), turned into a [`QpProblem`] with
//! A = P, f = −q, B = G, g = h and the reference answer.

use std::collections::HashMap;
use std::path::Path;

use signorini_core::qp::{CscMatrix, QpProblem};

use super::npz::read_npz;
use super::QpsetError;

/// One problem of a set.
#[derive(Debug, Clone)]
pub struct SetProblem {
    /// Its name (the file's stem).
    pub name: String,
    /// A = P, f = −q, B = G, g = h, and the null space of P when stored.
    pub qp: QpProblem,
    /// The reference x and z.
    pub reference: (Vec<f64>, Vec<f64>),
}

fn bad(path: &Path, why: impl Into<String>) -> QpsetError {
    QpsetError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::new(std::io::ErrorKind::InvalidData, why.into()),
    }
}

/// Every member of the archive by name (without `.npy`), values as f64.
fn members(path: &Path) -> Result<HashMap<String, Vec<f64>>, QpsetError> {
    let file = std::fs::File::open(path).map_err(|source| QpsetError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let arrays = read_npz(std::io::BufReader::new(file)).map_err(|e| bad(path, e.to_string()))?;
    Ok(arrays.into_iter().map(|(k, a)| (k, a.values)).collect())
}

fn matrix(path: &Path, m: &HashMap<String, Vec<f64>>, key: &str) -> Result<CscMatrix, QpsetError> {
    let get = |k: &str| {
        m.get(&format!("{key}_{k}"))
            .ok_or_else(|| bad(path, format!("{key}_{k} missing")))
    };
    let ints = |k: &str| -> Result<Vec<usize>, QpsetError> {
        Ok(get(k)?.iter().map(|v| *v as usize).collect())
    };
    let shape = ints("shape")?;
    if shape.len() != 2 {
        return Err(bad(path, format!("{key}_shape is not 2 numbers")));
    }
    CscMatrix::try_new_csc(
        (shape[0], shape[1]),
        ints("indptr")?,
        ints("indices")?,
        get("data")?.clone(),
    )
    .map_err(|(_, _, _, e)| bad(path, format!("{key}: {e}")))
}

/// Reads `data/NAME.npz` of a set.
pub fn read_problem(path: &Path) -> Result<SetProblem, QpsetError> {
    let m = members(path)?;
    let vector = |k: &str| {
        m.get(k)
            .cloned()
            .ok_or_else(|| bad(path, format!("{k} missing")))
    };
    let (p, g) = (matrix(path, &m, "P")?, matrix(path, &m, "G")?);
    let n = p.cols();
    let load: Vec<f64> = vector("q")?.iter().map(|v| -v).collect();
    let mut qp =
        QpProblem::try_new(p, load, g, vector("h")?).map_err(|e| bad(path, e.to_string()))?;
    if let Some(kernel) = m.get("kernel") {
        let modes = kernel.chunks(n.max(1)).map(<[f64]>::to_vec).collect();
        qp = qp
            .with_kernel(modes)
            .map_err(|e| bad(path, e.to_string()))?;
    }
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    Ok(SetProblem {
        name,
        qp,
        reference: (vector("x_ref")?, vector("z_ref")?),
    })
}
