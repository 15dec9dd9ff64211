//! Reading a set's problem back: the `.npz` files [`super::write_set`] writes (stored ZIP
//! members, `.npy` version 1.0, `<f8` or `<i4`), turned into a [`QpProblem`] with
//! A = P, f = −q, B = G, g = h and the reference answer.

use std::collections::HashMap;
use std::path::Path;

use signorini_core::qp::{CscMatrix, QpProblem};

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

fn u16_at(b: &[u8], at: usize) -> Option<usize> {
    Some(u16::from_le_bytes([*b.get(at)?, *b.get(at + 1)?]) as usize)
}

fn u32_at(b: &[u8], at: usize) -> Option<usize> {
    let s = b.get(at..at + 4)?;
    Some(u32::from_le_bytes([s[0], s[1], s[2], s[3]]) as usize)
}

/// One `.npy` member's values as f64.
fn npy(bytes: &[u8]) -> Option<Vec<f64>> {
    if bytes.get(..6)? != b"\x93NUMPY" {
        return None;
    }
    let len = u16_at(bytes, 8)?;
    let header = std::str::from_utf8(bytes.get(10..10 + len)?).ok()?;
    let body = bytes.get(10 + len..)?;
    if header.contains("'<f8'") {
        Some(
            body.chunks_exact(8)
                .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
                .collect(),
        )
    } else if header.contains("'<i4'") {
        Some(
            body.chunks_exact(4)
                .map(|c| f64::from(i32::from_le_bytes([c[0], c[1], c[2], c[3]])))
                .collect(),
        )
    } else {
        None
    }
}

/// Every member of the archive by name (without `.npy`).
fn members(path: &Path) -> Result<HashMap<String, Vec<f64>>, QpsetError> {
    let bytes = std::fs::read(path).map_err(|source| QpsetError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let mut out = HashMap::new();
    let mut at = 0;
    while u32_at(&bytes, at) == Some(0x0403_4b50) {
        let field = |k| u32_at(&bytes, at + k).ok_or_else(|| bad(path, "truncated"));
        let size = field(18)?;
        let name_len = u16_at(&bytes, at + 26).ok_or_else(|| bad(path, "truncated"))?;
        let extra = u16_at(&bytes, at + 28).ok_or_else(|| bad(path, "truncated"))?;
        if u16_at(&bytes, at + 8) != Some(0) {
            return Err(bad(path, "a compressed member (only stored ones are read)"));
        }
        let name = bytes
            .get(at + 30..at + 30 + name_len)
            .and_then(|n| std::str::from_utf8(n).ok())
            .ok_or_else(|| bad(path, "bad member name"))?;
        let start = at + 30 + name_len + extra;
        let data = bytes
            .get(start..start + size)
            .ok_or_else(|| bad(path, "truncated"))?;
        let values = npy(data).ok_or_else(|| bad(path, format!("{name}: not an npy array")))?;
        out.insert(name.trim_end_matches(".npy").to_string(), values);
        at = start + size;
    }
    Ok(out)
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
