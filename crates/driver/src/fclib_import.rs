//! Reading FCLIB's global form (`signorini compare --fclib FILE`): the HDF5 layout
//! [`crate::fclib`] writes, as FCLIB's `fclib_read_global` and `fclib_read_solution` read it,
//! turned back into our QP so that every backend can run on a problem from this or another code.
//!
//! Accepted: `/fclib_global` with `spacedim` = 2, the matrices `M` and `H` in any of FCLIB's
//! three storages (`nz` = −1 compressed columns, −2 compressed rows, ≥ 0 triplets with `p` the
//! row and `i` the column indices), `vectors/f`, `w`, `mu`, an optional `info/title`, and an
//! optional `/solution` (`v`, `u`, `r`).  Refused, with the reason: a 3-D problem (spacedim 3,
//! a second-order cone per contact, which our 2-D box rows do not state), equality constraints
//! (`G`, `b`), an M that is not symmetric (to [`crate::qp_files::SYMMETRY_TOLERANCE`] · max|M|;
//! a symmetric one is replaced by (M + Mᵀ)/2 as `compare --qp` does), indices out of range,
//! lengths that disagree, and μ negative or not finite.
//!
//! The map back is the inverse of the export's (see [`crate::fclib`]'s module docs): per
//! contact α, the normal row Bₙ = −H[:, 2α]ᵀ with gap gₙ = w[2α]; and, when μ_α > 0, a
//! tangential row Bₜ = −H[:, 2α+1]ᵀ with gₜ = w[2α+1] in the box block, linked to its normal
//! row by Coulomb's bound μ_α λₙ.  A contact with μ = 0 has r_T = 0 (its cone is a half-line)
//! and no tangential row.  M is A, f is f: `min ½vᵀMv − fᵀv` under those rows is the problem
//! our Coulomb solve (docs/scene.md, "Friction") answers, and r = (λₙ, λₜ) per contact.

use std::path::Path;

use hdf5_metno as hdf5;
use hdf5_metno::types::FixedAscii;
use signorini_core::model::TangentialRow;
use signorini_core::qp::{ConstraintBlock, CscMatrix, QpProblem};
use signorini_core::scene::Friction;

use crate::fclib::{FclibError, FclibGlobal, FclibMatrix, FclibSolution};
use crate::qp_files::SYMMETRY_TOLERANCE;

/// An FCLIB file: the global problem and, when the file holds one, its solution.
#[derive(Debug, Clone)]
pub struct FclibFile {
    /// The problem (matrices in compressed columns, whatever the file's storage).
    pub problem: FclibGlobal,
    /// `/solution`, when present.
    pub solution: Option<FclibSolution>,
}

/// Our QP of an FCLIB problem, with the Coulomb links of its tangential rows.
#[derive(Debug, Clone)]
pub struct ImportedQp {
    /// `min ½xᵀAx − fᵀx` under the normal rows (one non-negative block, one row per contact)
    /// and the tangential rows of the contacts with μ > 0 (one box block after it).
    pub qp: QpProblem,
    /// One per tangential row, in row order: its normal row and μ.
    pub tangential: Vec<TangentialRow>,
}

fn format_error(path: &Path, reason: impl Into<String>) -> FclibError {
    FclibError::Format {
        path: path.to_path_buf(),
        reason: reason.into(),
    }
}

fn hdf5_error(path: &Path) -> impl Fn(hdf5::Error) -> FclibError + '_ {
    move |source| FclibError::Read {
        path: path.to_path_buf(),
        source,
    }
}

/// Reads `path` (see the module docs).
pub fn read(path: &Path) -> Result<FclibFile, FclibError> {
    let err = hdf5_error(path);
    let file = hdf5::File::open(path).map_err(&err)?;
    if !file.link_exists("fclib_global") {
        let what = if file.link_exists("fclib_local") {
            "a local problem (/fclib_local: W, q, mu): only the global form (/fclib_global: M, H, f, w, mu) maps to our QP"
        } else {
            "no /fclib_global group: not an FCLIB global problem"
        };
        return Err(format_error(path, what));
    }
    let global = file.group("fclib_global").map_err(&err)?;
    let spacedim = scalar_int(&global, "spacedim").map_err(&err)?;
    if spacedim != 2 {
        return Err(format_error(
            path,
            format!("spacedim = {spacedim}: a {spacedim}-D problem (a second-order cone per contact); signorini solves 2-D contact (spacedim 2) only"),
        ));
    }
    if global.link_exists("G") {
        return Err(format_error(
            path,
            "equality constraints (G, b) are not supported: our QP has contact rows only",
        ));
    }
    let m = read_matrix(path, &global.group("M").map_err(&err)?)?;
    let h = read_matrix(path, &global.group("H").map_err(&err)?)?;
    let vectors = global.group("vectors").map_err(&err)?;
    let vector = |name: &str| -> Result<Vec<f64>, FclibError> {
        vectors
            .dataset(name)
            .map_err(&err)?
            .read_raw()
            .map_err(&err)
    };
    let (f, w, mu) = (vector("f")?, vector("w")?, vector("mu")?);
    let title = global
        .group("info")
        .ok()
        .and_then(|info| info.dataset("title").ok())
        .and_then(|d| d.read_scalar::<FixedAscii<1024>>().ok())
        .map(|t| t.as_str().trim_end_matches('\0').trim().to_string())
        .unwrap_or_default();
    let problem = FclibGlobal {
        m,
        h,
        f,
        w,
        mu,
        title,
        description: String::new(),
    };
    check_sizes(path, &problem)?;
    let solution = if file.link_exists("solution") {
        let s = file.group("solution").map_err(&err)?;
        let v = |name: &str| -> Result<Vec<f64>, FclibError> {
            s.dataset(name).map_err(&err)?.read_raw().map_err(&err)
        };
        let solution = FclibSolution {
            v: v("v")?,
            u: v("u")?,
            r: v("r")?,
        };
        if solution.v.len() != problem.f.len() || solution.r.len() != problem.w.len() {
            return Err(format_error(
                path,
                format!(
                    "/solution: v has {} entries and r {}, the problem {} unknowns and {} local ones",
                    solution.v.len(),
                    solution.r.len(),
                    problem.f.len(),
                    problem.w.len()
                ),
            ));
        }
        Some(solution)
    } else {
        None
    };
    Ok(FclibFile { problem, solution })
}

/// The one integer of a dataset of shape (1,) or a scalar.
fn scalar_int(group: &hdf5::Group, name: &str) -> hdf5::Result<i32> {
    let values: Vec<i32> = group.dataset(name)?.read_raw()?;
    values
        .first()
        .copied()
        .ok_or_else(|| hdf5::Error::from(format!("{name} is empty")))
}

/// Sizes of M, H and the vectors agree (n × n, n × 2nc, f n, w 2nc, μ nc).
fn check_sizes(path: &Path, p: &FclibGlobal) -> Result<(), FclibError> {
    let (n, local) = (p.m.n as usize, p.h.n as usize);
    let mut wrong = Vec::new();
    if p.m.m != p.m.n {
        wrong.push(format!("M is {}×{}, not square", p.m.m, p.m.n));
    }
    if p.h.m as usize != n {
        wrong.push(format!("H has {} rows, M {}", p.h.m, n));
    }
    if local % 2 != 0 {
        wrong.push(format!("H has {local} columns, not 2 per contact"));
    }
    if p.f.len() != n {
        wrong.push(format!("f has {} entries, M {} rows", p.f.len(), n));
    }
    if p.w.len() != local {
        wrong.push(format!("w has {} entries, H {} columns", p.w.len(), local));
    }
    if p.mu.len() * 2 != local {
        wrong.push(format!(
            "mu has {} entries, H {} columns (2 per contact)",
            p.mu.len(),
            local
        ));
    }
    if let Some(bad) = p.mu.iter().find(|m| !(m.is_finite() && **m >= 0.0)) {
        wrong.push(format!("mu holds {bad}: must be finite and >= 0"));
    }
    if wrong.is_empty() {
        Ok(())
    } else {
        Err(format_error(path, wrong.join("; ")))
    }
}

/// An FCLIB matrix group in any of its storages, as compressed columns.
fn read_matrix(path: &Path, group: &hdf5::Group) -> Result<FclibMatrix, FclibError> {
    let err = hdf5_error(path);
    let name = group.name();
    let (m, n, nz) = (
        scalar_int(group, "m").map_err(&err)?,
        scalar_int(group, "n").map_err(&err)?,
        scalar_int(group, "nz").map_err(&err)?,
    );
    let p: Vec<i32> = group.dataset("p").map_err(&err)?.read_raw().map_err(&err)?;
    let i: Vec<i32> = group.dataset("i").map_err(&err)?.read_raw().map_err(&err)?;
    let x: Vec<f64> = group.dataset("x").map_err(&err)?.read_raw().map_err(&err)?;
    let bad = |why: String| format_error(path, format!("{name}: {why}"));
    let (rows, cols) = match (usize::try_from(m), usize::try_from(n)) {
        (Ok(r), Ok(c)) => (r, c),
        _ => return Err(bad(format!("negative size {m}×{n}"))),
    };
    let entries = triplets(&p, &i, &x, nz, rows, cols).map_err(bad)?;
    let mut t = sprs::TriMat::new((rows, cols));
    for (r, c, v) in entries {
        t.add_triplet(r, c, v);
    }
    let a: CscMatrix = t.to_csc();
    Ok(FclibMatrix {
        m,
        n,
        p: a.indptr().raw_storage().iter().map(|&k| k as i32).collect(),
        i: a.indices().iter().map(|&k| k as i32).collect(),
        x: a.data().to_vec(),
    })
}

/// The entries (row, column, value) of a matrix stored as FCLIB stores it (`nz` = −1 compressed
/// columns, −2 compressed rows, ≥ 0 triplets), every index checked against the sizes.
fn triplets(
    p: &[i32],
    i: &[i32],
    x: &[f64],
    nz: i32,
    rows: usize,
    cols: usize,
) -> Result<Vec<(usize, usize, f64)>, String> {
    let index = |v: i32, bound: usize, what: &str| -> Result<usize, String> {
        usize::try_from(v)
            .ok()
            .filter(|&k| k < bound)
            .ok_or_else(|| format!("{what} index {v} out of range 0..{bound}"))
    };
    if nz >= 0 {
        let count = nz as usize;
        if p.len() < count || i.len() < count || x.len() < count {
            return Err(format!(
                "triplet storage with nz = {nz} but p, i, x hold {}, {}, {}",
                p.len(),
                i.len(),
                x.len()
            ));
        }
        return (0..count)
            .map(|k| {
                Ok((
                    index(p[k], rows, "row")?,
                    index(i[k], cols, "column")?,
                    x[k],
                ))
            })
            .collect();
    }
    let (outer, inner, transposed) = match nz {
        -1 => (cols, rows, false),
        -2 => (rows, cols, true),
        _ => {
            return Err(format!(
                "unknown storage nz = {nz} (FCLIB: -1 CSC, -2 CSR, >= 0 triplets)"
            ))
        }
    };
    if p.len() != outer + 1 {
        return Err(format!(
            "{} pointers for {outer} {}",
            p.len(),
            if transposed { "rows" } else { "columns" }
        ));
    }
    let mut out = Vec::with_capacity(x.len());
    for o in 0..outer {
        let (a, b) = (p[o], p[o + 1]);
        let ok = |v: i32| {
            usize::try_from(v)
                .ok()
                .filter(|&k| k <= i.len() && k <= x.len())
        };
        let (Some(a), Some(b)) = (ok(a), ok(b)) else {
            return Err(format!(
                "pointer {a}..{b} beyond the {} stored entries",
                i.len().min(x.len())
            ));
        };
        if a > b {
            return Err(format!("pointers decrease at {o}: {a} > {b}"));
        }
        for k in a..b {
            let j = index(i[k], inner, if transposed { "column" } else { "row" })?;
            out.push(if transposed {
                (o, j, x[k])
            } else {
                (j, o, x[k])
            });
        }
    }
    Ok(out)
}

/// M as our A: checked symmetric to [`SYMMETRY_TOLERANCE`] · max|M| and symmetrised.
fn stiffness(path: &Path, m: &FclibMatrix) -> Result<CscMatrix, FclibError> {
    let a = csc(m);
    let at: CscMatrix = a.transpose_view().to_csc();
    let largest = a.data().iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    let diff: CscMatrix = &a - &at;
    let worst = diff.data().iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    if worst > SYMMETRY_TOLERANCE * largest {
        return Err(format_error(
            path,
            format!(
                "M is not symmetric: max |M - Mt| = {worst:e} against max |M| = {largest:e} (our backends solve symmetric problems)"
            ),
        ));
    }
    let sum: CscMatrix = &a + &at;
    Ok(sum.map(|v| 0.5 * v))
}

fn csc(m: &FclibMatrix) -> CscMatrix {
    let p = m.p.iter().map(|&k| k as usize).collect();
    let i = m.i.iter().map(|&k| k as usize).collect();
    // Valid by construction: `read_matrix` stores what `TriMat::to_csc` built.
    CscMatrix::new_csc((m.m as usize, m.n as usize), p, i, m.x.clone())
}

impl FclibFile {
    /// Our QP of the problem (see the module docs); `path` names the file in errors.
    pub fn to_qp(&self, path: &Path) -> Result<ImportedQp, FclibError> {
        let p = &self.problem;
        let contacts = p.mu.len();
        let slot_of: Vec<Option<usize>> =
            p.mu.iter()
                .scan(0, |next, &mu| {
                    Some((mu > 0.0).then(|| {
                        *next += 1;
                        *next - 1
                    }))
                })
                .collect();
        let frictional = slot_of.iter().flatten().count();
        let n = p.f.len();
        let rows = contacts + frictional;
        let row_of = |col: usize| -> Option<usize> {
            let alpha = col / 2;
            if col.is_multiple_of(2) {
                Some(alpha)
            } else {
                slot_of[alpha].map(|s| contacts + s)
            }
        };
        let mut b = sprs::TriMat::new((rows, n));
        let mut gap = vec![0.0; rows];
        let h = csc(&p.h);
        for (col, column) in h.outer_iterator().enumerate() {
            if let Some(row) = row_of(col) {
                for (dof, v) in column.iter() {
                    b.add_triplet(row, dof, -v);
                }
                gap[row] = p.w[col];
            }
        }
        let tangential: Vec<TangentialRow> =
            p.mu.iter()
                .enumerate()
                .filter(|(_, &mu)| mu > 0.0)
                .map(|(alpha, &mu)| TangentialRow {
                    normal_row: alpha,
                    pair: 0,
                    law: Friction::Coulomb(mu),
                    tributary: 1.0,
                    // FCLIB gives the rows' gaps (w) directly: no pairing to account for.
                    pairing_slope: 0.0,
                })
                .collect();
        let mut blocks = vec![ConstraintBlock::NonNegative { rows: contacts }];
        if frictional > 0 {
            blocks.push(ConstraintBlock::Box {
                bounds: vec![0.0; frictional],
            });
        }
        let qp = QpProblem::try_new(stiffness(path, &p.m)?, p.f.clone(), b.to_csc(), gap)
            .and_then(|qp| qp.with_blocks(blocks))
            .map_err(|e| format_error(path, e.to_string()))?;
        Ok(ImportedQp { qp, tangential })
    }
}

/// How far an answer (v, r) lies from a stored one: max |v − v*| / max |v*| and
/// max |r − r*| / max |r*| (absolute when the stored vector is zero).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct StoredDifference {
    /// Relative difference of v.
    pub v: f64,
    /// Relative difference of r.
    pub r: f64,
}

impl StoredDifference {
    /// `ours` against `stored`.
    pub fn of(ours: &FclibSolution, stored: &FclibSolution) -> Self {
        fn relative(a: &[f64], b: &[f64]) -> f64 {
            let scale = b.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
            let diff = a
                .iter()
                .zip(b)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0_f64, |m, d| {
                    if d.is_nan() || m.is_nan() {
                        f64::NAN
                    } else {
                        m.max(d)
                    }
                });
            if scale > 0.0 {
                diff / scale
            } else {
                diff
            }
        }
        Self {
            v: relative(&ours.v, &stored.v),
            r: relative(&ours.r, &stored.r),
        }
    }
}
