//! `signorini export --fclib FILE`: a scene's contact problem in FCLIB's global form (the HDF5
//! layout of the Frictional Contact Library, Acary, Cadoux, Lemaréchal, Malick; INRIA RT-0444),
//! so the frictional-contact community's solvers (Siconos and its `faf` comparisons) can run it.
//!
//! FCLIB's global problem, for nc contacts in 2D (spacedim 2, local vectors (N, T) per contact):
//!
//! ```text
//! M v = H r + f,     u = Hᵀ v + w,     C*_μ ∋ û ⟂ r ∈ C_μ,
//! C_μ = { r : |r_T| ≤ μ r_N },   û = u + (μ |u_T|, 0) per contact.
//! ```
//!
//! Ours, `min ½xᵀAx − fᵀx` with normal rows `Bₙx ≤ gₙ` (multipliers λₙ ≥ 0) and each frictional
//! node's tangential row `Bₜx − gₜ` (its slip; λₜ opposes it, |λₜ| ≤ μλₙ), maps as M = A (the
//! stiffness: a quasi-static problem, v the displacement), f = f, and per contact α (a normal
//! row) the columns 2α = −Bₙᵀ and 2α+1 = −Bₜᵀ of H, w = (gₙ, gₜ): then u_N = gₙ − Bₙx is the
//! gap, u_T = −(Bₜx − gₜ) the slip seen from the master, r = (λₙ, λₜ), and stationarity
//! A x = f − Bᵀλ is M v = H r + f.  A contact without friction has μ = 0 and a zero tangential
//! column.  The unknowns are the free DOFs, the values the user's units (as the Matrix Market
//! export).  Tresca's fixed bound is not a Coulomb cone: it is refused rather than written as a
//! different problem.
//!
//! A load path (`[[step]]`) is written as FCLIB's libraries hold sequences of problems (LMGC90's
//! and Siconos' dumps: one file per solved problem, its number the last `-`-separated field of
//! the name, e.g. `LMGC_Cubes_H8-i00012-361-00041.hdf5`): one file per increment,
//! `STEM-00001.hdf5`, `STEM-00002.hdf5`, … beside FILE ([`numbered`]).  Each is the increment's
//! own problem: f and the normal gaps of its loads and prescribed values, and on each tangential
//! entry of w the tangential row's stick value after the previous converged increment
//! (`TangentialRow::stick_value`: B_t u_prev for a node in contact), so that u_T is
//! this increment's slip (friction's history, docs/scene.md "Load steps").
//!
//! Layout (as FCLIB's `fclib_write_global` and `fclib_write_solution` write it): `/fclib_global`
//! with `spacedim` (int), the groups `M` and `H` (CSparse compressed columns: `nzmax`, `m`, `n`,
//! `nz` = −1 as ints, `p`, `i` (ints), `x`), `vectors` (`f`, `w`, `mu`) and `info` (`title`,
//! `description`, `math_info`: fixed-length ASCII strings); `/solution` with `v`, `u`, `r` when
//! a solve gave one.

use std::path::{Path, PathBuf};

use hdf5_metno as hdf5;
use hdf5_metno::types::FixedAscii;
use signorini_core::model::Model;
use signorini_core::qp::{CscMatrix, QpProblem};
use signorini_core::scene::{Friction, Plane, Scene};
use signorini_core::solve::Solution;

/// Why a scene cannot be exported to FCLIB, or the file not written.
#[derive(Debug, thiserror::Error)]
pub enum FclibError {
    /// A pair's law FCLIB cannot state.
    #[error("contact #{pair}: FCLIB holds Coulomb friction (a cone |r_T| <= mu r_N); `tresca` (a fixed bound) has no FCLIB form")]
    Tresca {
        /// The pair, 1-based.
        pair: usize,
    },
    /// A load path.
    #[error("the scene has [[step]] tables: one FCLIB problem holds one increment (its slip measured from the previous one); write one file per increment (`FclibGlobal::increment`, `numbered`)")]
    LoadPath,
    /// The model and its QP disagree (a bug, reported rather than written).
    #[error("the QP has {qp} rows, the model {model}: nothing written")]
    Rows {
        /// Rows of the QP.
        qp: usize,
        /// Rows of the model.
        model: usize,
    },
    /// A size beyond FCLIB's 32-bit integers.
    #[error("{what} = {value} exceeds FCLIB's 32-bit indices")]
    TooLarge {
        /// What overflowed.
        what: &'static str,
        /// Its value.
        value: usize,
    },
    /// The HDF5 library refused.
    #[error("writing {path}")]
    Hdf5 {
        /// The file.
        path: PathBuf,
        /// HDF5's error.
        source: hdf5::Error,
    },
    /// Reading an FCLIB file: it is missing, not HDF5, or lacks a dataset FCLIB requires.
    #[error("reading {path}")]
    Read {
        /// The file.
        path: PathBuf,
        /// HDF5's error.
        source: hdf5::Error,
    },
    /// An FCLIB file whose contents our QP cannot state or that contradict each other.
    #[error("{path}: {reason}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// Moving the finished file into place.
    #[error("moving the finished file to {path}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}

/// A compressed-column matrix with FCLIB's 32-bit indices.
#[derive(Debug, Clone, PartialEq)]
pub struct FclibMatrix {
    /// Rows.
    pub m: i32,
    /// Columns.
    pub n: i32,
    /// Column pointers (n + 1).
    pub p: Vec<i32>,
    /// Row indices (nnz).
    pub i: Vec<i32>,
    /// Values (nnz).
    pub x: Vec<f64>,
}

fn int(what: &'static str, value: usize) -> Result<i32, FclibError> {
    i32::try_from(value).map_err(|_| FclibError::TooLarge { what, value })
}

impl FclibMatrix {
    /// From a sparse matrix in compressed columns.
    fn of(a: &CscMatrix) -> Result<Self, FclibError> {
        let (m, n) = a.shape();
        let mut p = Vec::with_capacity(n + 1);
        let (mut i, mut x) = (Vec::with_capacity(a.nnz()), Vec::with_capacity(a.nnz()));
        p.push(0);
        for col in a.outer_iterator() {
            for (row, v) in col.iter() {
                i.push(int("row index", row)?);
                x.push(*v);
            }
            p.push(int("nnz", i.len())?);
        }
        Ok(Self {
            m: int("rows", m)?,
            n: int("columns", n)?,
            p,
            i,
            x,
        })
    }
}

/// FCLIB's global problem (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct FclibGlobal {
    /// The stiffness A (n × n, both triangles).
    pub m: FclibMatrix,
    /// H = −[Bₙ; Bₜ]ᵀ interleaved per contact (n × 2nc).
    pub h: FclibMatrix,
    /// The load f.
    pub f: Vec<f64>,
    /// w = (gₙ, gₜ) interleaved per contact.
    pub w: Vec<f64>,
    /// μ per contact (0 without friction).
    pub mu: Vec<f64>,
    /// `info/title`.
    pub title: String,
    /// `info/description`.
    pub description: String,
}

/// FCLIB's solution: v (the free DOFs' displacements), u = Hᵀv + w and r (the multipliers).
#[derive(Debug, Clone, PartialEq)]
pub struct FclibSolution {
    /// v.
    pub v: Vec<f64>,
    /// u.
    pub u: Vec<f64>,
    /// r.
    pub r: Vec<f64>,
}

/// Refuses a model FCLIB cannot state (a Tresca pair): to check before any solve.
pub fn check_laws(model: &Model) -> Result<(), FclibError> {
    contacts(model).map(|_| ())
}

/// Per contact (normal row): its tangential row and μ, if the node has friction.
fn contacts(model: &Model) -> Result<Vec<Option<(usize, f64)>>, FclibError> {
    let first = model.normal_rows();
    let mut links = vec![None; first];
    for (slot, t) in model.tangential.iter().enumerate() {
        match t.law {
            Friction::Coulomb(mu) => {
                if let Some(l) = links.get_mut(t.normal_row) {
                    *l = Some((first + slot, mu));
                }
            }
            Friction::Tresca(_) => return Err(FclibError::Tresca { pair: t.pair + 1 }),
        }
    }
    Ok(links)
}

impl FclibGlobal {
    /// The FCLIB form of `qp`, the reduced problem of `model` (see the module docs); a scene
    /// with a load path is refused (see [`FclibGlobal::increment`]).
    pub fn of(scene: &Scene, model: &Model, qp: &QpProblem) -> Result<Self, FclibError> {
        if !scene.steps.is_empty() {
            return Err(FclibError::LoadPath);
        }
        Self::of_increment(scene, model, qp, None)
    }

    /// The FCLIB form of one increment of a load path: `qp` is that increment's problem
    /// ([`signorini_core::solve::increment_problem`]: its w holds the gaps of this increment
    /// and, on each tangential entry, B_t u of the previous converged increment, so that u_T is
    /// this increment's slip); `label` (step, increment) goes into the title.
    pub fn increment(
        scene: &Scene,
        model: &Model,
        qp: &QpProblem,
        label: (usize, usize),
    ) -> Result<Self, FclibError> {
        Self::of_increment(scene, model, qp, Some(label))
    }

    fn of_increment(
        scene: &Scene,
        model: &Model,
        qp: &QpProblem,
        label: Option<(usize, usize)>,
    ) -> Result<Self, FclibError> {
        if qp.rows() != model.gap.len() {
            return Err(FclibError::Rows {
                qp: qp.rows(),
                model: model.gap.len(),
            });
        }
        let links = contacts(model)?;
        let b = qp.constraints.to_csr();
        let n = qp.dofs();
        let mut h = sprs::TriMat::new((n, 2 * links.len()));
        let mut w = vec![0.0; 2 * links.len()];
        let mut mu = vec![0.0; links.len()];
        for (alpha, link) in links.iter().enumerate() {
            let mut column = |row: usize, col: usize| {
                if let Some(r) = b.outer_view(row) {
                    for (j, v) in r.iter() {
                        h.add_triplet(j, col, -v);
                    }
                }
                w[col] = qp.gap[row];
            };
            column(alpha, 2 * alpha);
            if let Some((row, m)) = *link {
                column(row, 2 * alpha + 1);
                mu[alpha] = m;
            }
        }
        let h: CscMatrix = h.to_csc();
        Ok(Self {
            m: FclibMatrix::of(&qp.stiffness)?,
            h: FclibMatrix::of(&h)?,
            f: qp.load.clone(),
            w,
            mu,
            title: match label {
                Some((step, increment)) => {
                    format!("{} (step {step}, increment {increment})", scene.title)
                }
                None => scene.title.clone(),
            },
            description: format!(
                "signorini: 2D linear-elastic contact, plane {}, {} unknowns (free DOFs), {} contacts; \
                 M is the stiffness (quasi-static: v is the displacement), r = (normal, tangential) \
                 contact forces per contact, u = (gap, -slip)",
                match scene.plane {
                    Plane::Stress => "stress",
                    Plane::Strain => "strain",
                },
                n,
                links.len()
            ),
        })
    }

    /// FCLIB's solution from ours: v = x on the free DOFs, r = (λₙ, λₜ) per contact, u = Hᵀv + w.
    pub fn solution(&self, model: &Model, solution: &Solution) -> FclibSolution {
        let v: Vec<f64> = model
            .free
            .iter()
            .map(|&d| solution.displacement[d])
            .collect();
        let contacts = self.mu.len();
        let first = model.normal_rows();
        let mut r = vec![0.0; 2 * contacts];
        for (alpha, pair) in r.chunks_mut(2).enumerate() {
            pair[0] = solution.multipliers.get(alpha).copied().unwrap_or(0.0);
        }
        for (slot, t) in model.tangential.iter().enumerate() {
            if let Some(x) = r.get_mut(2 * t.normal_row + 1) {
                *x = solution
                    .multipliers
                    .get(first + slot)
                    .copied()
                    .unwrap_or(0.0);
            }
        }
        let mut u = self.w.clone();
        for (col, u) in u.iter_mut().enumerate() {
            let (a, b) = (self.h.p[col] as usize, self.h.p[col + 1] as usize);
            for k in a..b {
                *u += self.h.x[k] * v[self.h.i[k] as usize];
            }
        }
        FclibSolution { v, u, r }
    }
}

/// The file of increment `k` (1-based) of a load path exported to `file`: `STEM-0000k.EXT`
/// beside it (five digits, more when k needs them; `.hdf5` when `file` has no extension).
pub fn numbered(file: &Path, k: usize) -> PathBuf {
    let stem = file
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = file
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_else(|| "hdf5".to_string());
    file.with_file_name(format!("{stem}-{k:05}.{ext}"))
}

/// Up to 1024 ASCII characters of `text` (others become `?`), as FCLIB's fixed-length strings.
fn ascii(text: &str) -> FixedAscii<1024> {
    let bytes: Vec<u8> = text
        .chars()
        .map(|c| {
            if c.is_ascii() && c != '\0' {
                c as u8
            } else {
                b'?'
            }
        })
        .take(1024)
        .collect();
    FixedAscii::from_ascii(&bytes).unwrap_or_default()
}

fn write_matrix(group: &hdf5::Group, a: &FclibMatrix) -> hdf5::Result<()> {
    let nnz = a.x.len() as i32;
    for (name, value) in [("nzmax", nnz), ("m", a.m), ("n", a.n), ("nz", -1)] {
        group
            .new_dataset_builder()
            .with_data(&[value])
            .create(name)?;
    }
    group.new_dataset_builder().with_data(&a.p).create("p")?;
    group.new_dataset_builder().with_data(&a.i).create("i")?;
    group.new_dataset_builder().with_data(&a.x).create("x")?;
    Ok(())
}

fn write_vector(group: &hdf5::Group, name: &str, v: &[f64]) -> hdf5::Result<()> {
    group.new_dataset_builder().with_data(v).create(name)?;
    Ok(())
}

fn write_string(group: &hdf5::Group, name: &str, text: &str) -> hdf5::Result<()> {
    group
        .new_dataset::<FixedAscii<1024>>()
        .create(name)?
        .write_scalar(&ascii(text))
}

fn write_file(path: &Path, p: &FclibGlobal, s: Option<&FclibSolution>) -> hdf5::Result<()> {
    let file = hdf5::File::create(path)?;
    let global = file.create_group("fclib_global")?;
    global
        .new_dataset_builder()
        .with_data(&[2i32])
        .create("spacedim")?;
    write_matrix(&global.create_group("M")?, &p.m)?;
    write_matrix(&global.create_group("H")?, &p.h)?;
    let vectors = global.create_group("vectors")?;
    write_vector(&vectors, "f", &p.f)?;
    write_vector(&vectors, "w", &p.w)?;
    write_vector(&vectors, "mu", &p.mu)?;
    let info = global.create_group("info")?;
    write_string(&info, "title", &p.title)?;
    write_string(&info, "description", &p.description)?;
    write_string(
        &info,
        "math_info",
        "M symmetric positive semi-definite (singular when a body is held by contact alone)",
    )?;
    if let Some(s) = s {
        let solution = file.create_group("solution")?;
        write_vector(&solution, "v", &s.v)?;
        write_vector(&solution, "u", &s.u)?;
        write_vector(&solution, "r", &s.r)?;
    }
    file.close()
}

/// Writes `problem` (and `solution`) to `path`: into a temporary file beside it, moved into place
/// when complete, so a failed export leaves no file or the previous one.
pub fn write(
    path: &Path,
    problem: &FclibGlobal,
    solution: Option<&FclibSolution>,
) -> Result<(), FclibError> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let io = |source| FclibError::Io {
        path: path.to_path_buf(),
        source,
    };
    let temp = tempfile::Builder::new()
        .prefix(".fclib-")
        .suffix(".hdf5.part")
        .tempfile_in(dir)
        .map_err(io)?;
    write_file(temp.path(), problem, solution).map_err(|source| FclibError::Hdf5 {
        path: path.to_path_buf(),
        source,
    })?;
    temp.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}
