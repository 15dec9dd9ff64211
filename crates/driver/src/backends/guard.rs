//! The memory guard of a run: the run's peak — what the solve path holds (the scaled problem, the
//! model's copy of B, the copies a Coulomb solve or a load path makes) plus what the backend
//! holds at once (its factor, its dense or sparse working arrays) — priced before anything large
//! is allocated, and refused when it exceeds the memory available ([`memory::available_bytes`]:
//! `MemAvailable`, capped by `SIGNORINI_MEMORY_LIMIT`).
//!
//! `signorini check` prints these figures ([`crate::check::memory_needs`]) and `solve` refuses
//! exactly when its figure does not fit ([`guard_run`]: exit 3, nothing written), so the two
//! agree.  Each backend states its own estimate in its row of the registry
//! ([`crate::backends::Entry::need`]); there is no catch-all.
//!
//! While the backend runs, the solve path's part is held ([`memory::hold`]) so that every check
//! a backend makes before an allocation of its own counts it (and the dual backends hold their
//! factor of A while they form the dense H): the backend's own checks, each at most its part of
//! the estimate, cannot refuse a run the guard let through, and a backend with a leaner path
//! (dual-ssn's matrix-free Newton steps) takes it when the dense one would not fit beside what is
//! held.

use signorini_core::linalg::CholeskyPattern;
use signorini_core::memory::{self, FactorEstimate, Held, GIB};
use signorini_core::model::Model;
use signorini_core::qp::{touched_dofs, CscMatrix, QpError, QpProblem, BYTES_PER_DUAL_ENTRY};

use crate::backends::BackendKind;

/// What a run on one QP looks like to the estimates: the problem, the analysis of its factor
/// of A, the solve path's copies and the memory available.
#[derive(Debug, Clone)]
pub struct RunShape<'a> {
    /// The QP the backend solves (its pattern and sizes; the scaled one has the same).
    pub qp: &'a QpProblem,
    /// The factor of A from its symbolic analysis (the dual backends factor A).
    pub base: FactorEstimate,
    /// What the solve path holds besides the backend.
    pub path: Part,
    /// Memory available, bytes (`None`: unknown; then nothing is refused).
    pub available: Option<u64>,
    /// Whether the model has Coulomb rows (auto then tries a backend's own method first).
    pub coulomb: bool,
}

/// One part of a run's memory: bytes and what they are for.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// Bytes.
    pub bytes: f64,
    /// What they are for, for `check` and the refusal's message.
    pub what: String,
}

/// One backend's estimated peak for a run: the solve path's part plus its own.
#[derive(Debug, Clone, PartialEq)]
pub struct BackendNeed {
    /// The backend's command-line name.
    pub backend: &'static str,
    /// The run's peak, bytes: [`BackendNeed::path`] + [`BackendNeed::own`].
    pub bytes: f64,
    /// The solve path's part (held while the backend runs).
    pub path: f64,
    /// The backend's own part, bytes.
    pub own: f64,
    /// What the backend's own part is for.
    pub what: String,
}

/// Bytes of a CSC matrix: 12 B per entry (value, 32-bit-or-more index counted as 4 more than
/// the value's half: the same measure as [`FactorEstimate`]) and 8 B per column pointer.
fn csc_bytes(m: &CscMatrix) -> f64 {
    12.0 * m.nnz() as f64 + 8.0 * (m.cols() + 1) as f64
}

/// Bytes of one copy of `qp`: A, B, f, g and the kernel (n × k).
pub fn problem_bytes(qp: &QpProblem) -> f64 {
    let (n, m) = (qp.dofs() as f64, qp.rows() as f64);
    csc_bytes(&qp.stiffness)
        + csc_bytes(&qp.constraints)
        + 8.0 * (n + 2.0 * m)
        + 8.0 * n * qp.kernel.len() as f64
}

/// The solve path's part: the scaled problem with the model's copy of B and the vectors of n
/// ([`FactorEstimate::matrices`] and [`FactorEstimate::vectors`]), one more copy of the problem
/// for Coulomb's rows (the fixed point's, or the backend's own method's, with its bounds) and
/// one for a load path's increment.
pub fn path_part(model: &Model, qp: &QpProblem, base: &FactorEstimate) -> Part {
    let coulomb = has_coulomb(model);
    let steps = model.path.as_ref().is_some_and(|p| p.increments.len() > 1);
    let copies = usize::from(coulomb) + usize::from(steps);
    let mut what = "the scaled problem (A, B, the model's B, vectors)".to_string();
    if coulomb {
        what.push_str(", the Coulomb solve's copy of it");
    }
    if steps {
        what.push_str(", the load increment's copy of it");
    }
    Part {
        bytes: base.matrices + base.vectors + copies as f64 * problem_bytes(qp),
        what,
    }
}

/// Whether `model` has Coulomb rows.
fn has_coulomb(model: &Model) -> bool {
    model
        .tangential
        .iter()
        .any(|t| matches!(t.law, signorini_core::scene::Friction::Coulomb(_)))
}

impl<'a> RunShape<'a> {
    /// The shape of a run of `model`'s QP `qp` (analyses A: one symbolic factorisation).
    ///
    /// # Errors
    /// [`QpError::Backend`] when the analysis fails.
    pub fn of(model: &Model, qp: &'a QpProblem) -> Result<Self, QpError> {
        let base = analyse(qp)?;
        Ok(Self {
            qp,
            path: path_part(model, qp, &base),
            base,
            available: memory::available_bytes(),
            coulomb: has_coulomb(model),
        })
    }

    /// The run's peak with `kind`: the solve path's part plus the backend's own.
    ///
    /// # Errors
    /// What the backend's estimate returns (a failed symbolic analysis).
    pub fn need(&self, kind: BackendKind) -> Result<BackendNeed, QpError> {
        let own = (kind.entry().need)(self)?;
        Ok(BackendNeed {
            backend: kind.name(),
            bytes: self.path.bytes + own.bytes,
            path: self.path.bytes,
            own: own.bytes,
            what: own.what,
        })
    }

    /// Whether `bytes` fit in what is available (unknown: yes).
    pub fn fits(&self, bytes: f64) -> bool {
        self.available.is_none_or(|a| bytes <= a as f64)
    }

    /// The factor of A and its scratch, bytes: what a dual backend or a condensed dual adds.
    fn factor_of_a(&self) -> f64 {
        self.base.factor + self.base.scratch
    }
}

/// The symbolic analysis of A priced as [`FactorEstimate`].
///
/// # Errors
/// [`QpError::Backend`] when it fails.
pub fn analyse(qp: &QpProblem) -> Result<FactorEstimate, QpError> {
    let pattern = CholeskyPattern::analyse(&qp.stiffness).map_err(|e| QpError::Backend {
        backend: "memory guard",
        reason: format!("the symbolic analysis of A: {e}"),
    })?;
    Ok(FactorEstimate::of(qp, &pattern))
}

/// Before the solve of `kind` on the run `shape`: `Err(QpError::TooLarge)` naming the run's
/// peak (the figure `check` prints) when it does not fit, else the guard that holds the solve
/// path's part while the backend runs.
///
/// # Errors
/// [`QpError::TooLarge`]; what the estimate returns.
pub fn guard_run(kind: BackendKind, shape: &RunShape<'_>) -> Result<Held, QpError> {
    let need = shape.need(kind)?;
    refuse_unless_fits(&need, shape)?;
    Ok(memory::hold(need.path))
}

/// `Err(QpError::TooLarge)` when `need` does not fit in `shape`'s available memory.
///
/// # Errors
/// [`QpError::TooLarge`] with the run's peak.
pub fn refuse_unless_fits(need: &BackendNeed, shape: &RunShape<'_>) -> Result<(), QpError> {
    match shape.available {
        Some(available) if need.bytes > available as f64 => Err(QpError::TooLarge {
            backend: need.backend,
            what: format!(
                "the run's peak: {} ({}) and {} ({})",
                need.what,
                size(need.own),
                shape.path.what,
                size(need.path)
            ),
            needed: need.bytes / GIB,
            available: available as f64 / GIB,
        }),
        _ => Ok(()),
    }
}

/// Bytes in MiB for a message.
fn size(bytes: f64) -> String {
    format!("{:.1} MiB", bytes / (1024.0 * 1024.0))
}

/// The KKT backends' own part, from the symbolic analysis of K.
fn kkt_part(estimate: signorini_core::memory::KktEstimate, factors: &str) -> Part {
    Part {
        bytes: estimate.total(),
        what: format!(
            "{factors} of the {d}×{d} KKT matrix (nnz(L) = {v:.3e}), the solver's copies and vectors",
            d = estimate.dim,
            v = estimate.nnz_l as f64
        ),
    }
}

/// clarabel: its LDLᵀ factor of K, its copies of the data and its vectors
/// ([`signorini_clarabel::MEMORY_MODEL`]).
pub fn clarabel(shape: &RunShape<'_>) -> Result<Part, QpError> {
    Ok(kkt_part(
        signorini_clarabel::memory_need(shape.qp)?,
        "the LDLᵀ factor",
    ))
}

/// OSQP: two LDLᵀ factors of K (ADMM's, the polish's), copies and vectors
/// (`signorini_osqp::MEMORY_MODEL`).
#[cfg(feature = "osqp")]
pub fn osqp(shape: &RunShape<'_>) -> Result<Part, QpError> {
    Ok(kkt_part(
        signorini_osqp::memory_need(shape.qp)?,
        "two LDLᵀ factors (ADMM's, the polish's)",
    ))
}

/// OSQP without the `osqp` feature: never run (the backend is not compiled in), priced 0.
#[cfg(not(feature = "osqp"))]
pub fn osqp(_shape: &RunShape<'_>) -> Result<Part, QpError> {
    Ok(Part {
        bytes: 0.0,
        what: "not compiled in".into(),
    })
}

/// pdas: the factor of K, faer's workspace, K, its vectors and the cached columns of the
/// factor's inverse, from the very analysis the solve runs ([`signorini_pdas::memory_need`]).
pub fn pdas(shape: &RunShape<'_>) -> Result<Part, QpError> {
    let need = signorini_pdas::memory_need(shape.qp)?;
    Ok(Part {
        bytes: need.total(),
        what: format!(
            "the LDLᵀ factor of the {d}×{d} KKT matrix (nnz(L) = {v:.3e}) with its workspace, K, vectors and the cached columns of its inverse",
            d = need.dim,
            v = need.nnz_l as f64
        ),
    })
}

/// Most contact DOFs the dual backends order last ([`signorini_dual::MAX_TRAILING`]).
const MAX_TRAILING: f64 = signorini_dual::MAX_TRAILING as f64;

/// Right-hand sides per block of the multi-right-hand-side formation of H (the registry's
/// dual backends run with the default settings).
fn block_size() -> f64 {
    signorini_dual::DualSettings::default().block_size as f64
}

/// Rows above which dual-ssn takes matrix-free Newton steps (default settings).
fn matrix_free_rows() -> usize {
    signorini_dual::DualSettings::default().matrix_free_rows
}

/// The dense arrays a dual backend holds beside its sparse factor of A when it forms H, with
/// `extra` further m × m arrays, the larger of its two paths (`signorini_dual`'s `dense_bytes`
/// and the factor's dense block): with the c contact DOFs ordered last (c ≤ 6 000), the factor's
/// dense trailing block (c²), the trailing rows (c × m), H and its work copy (2 m²); else H (m²)
/// and one block of right-hand sides (n × 64).
fn dense_h(shape: &RunShape<'_>, extra: f64) -> f64 {
    let (n, m) = (shape.qp.dofs() as f64, shape.qp.rows() as f64);
    let c = touched_dofs(&shape.qp.constraints) as f64;
    let trailing = if c <= MAX_TRAILING {
        c * c + c * m + 2.0 * m * m
    } else {
        0.0
    };
    let blocks = m * m + n * block_size();
    8.0 * (trailing.max(blocks) + extra * m * m)
}

/// The dual backends' factor of A and its scratch ([`FactorEstimate`]) and their dense
/// trailing block, when they order the contact DOFs last and form no H (dual-uzawa does not
/// order them last; dual-ssn's matrix-free steps do).
fn dual_factor(shape: &RunShape<'_>) -> f64 {
    let c = touched_dofs(&shape.qp.constraints) as f64;
    let block = if c <= MAX_TRAILING { 8.0 * c * c } else { 0.0 };
    shape.factor_of_a() + block
}

/// A dual method's vectors besides the dense arrays: about twenty of m and ten of n.
fn dual_vectors(shape: &RunShape<'_>) -> f64 {
    8.0 * (20.0 * shape.qp.rows() as f64 + 10.0 * shape.qp.dofs() as f64)
}

/// dual-pgs: the factor of A and the dense dual Hessian H with its work arrays.
pub fn dual_pgs(shape: &RunShape<'_>) -> Result<Part, QpError> {
    Ok(Part {
        bytes: shape.factor_of_a() + dense_h(shape, 0.0) + dual_vectors(shape),
        what: "the factor of A and the dense dual Hessian H (m × m) with its work arrays".into(),
    })
}

/// dual-ssn: the factor of A with H, its Newton matrix, a shifted copy and their factor (three
/// m × m arrays besides H) when they fit beside the rest and m ≤ 20 000 (its
/// `matrix_free_rows`); else its matrix-free Newton steps, the factor of A alone.
pub fn dual_ssn(shape: &RunShape<'_>) -> Result<Part, QpError> {
    let m = shape.qp.rows();
    let dense = shape.factor_of_a() + dense_h(shape, 3.0) + dual_vectors(shape);
    let factor = dual_factor(shape) + dual_vectors(shape);
    if m <= matrix_free_rows() && shape.fits(shape.path.bytes + dense) {
        Ok(Part {
            bytes: dense,
            what: "the factor of A, H, its Newton matrix, a shifted copy and their factor (dense Newton steps)".into(),
        })
    } else {
        Ok(Part {
            bytes: factor + 8.0 * 10.0 * m as f64,
            what: "the factor of A and CG's vectors (matrix-free Newton steps: the dense ones do not fit)".into(),
        })
    }
}

/// dual-uzawa: the factor of A and its vectors (it never forms H).
pub fn dual_uzawa(shape: &RunShape<'_>) -> Result<Part, QpError> {
    Ok(Part {
        bytes: shape.factor_of_a() + dual_vectors(shape),
        what: "the factor of A and vectors (no dense matrix)".into(),
    })
}

/// A solver on the condensed dual: the factor of A, H with the inner solver's copy
/// ([`BYTES_PER_DUAL_ENTRY`] per entry) and one block of right-hand sides (64 MiB at most).
pub fn condensed(shape: &RunShape<'_>) -> Result<Part, QpError> {
    let (n, m) = (shape.qp.dofs() as f64, shape.qp.rows() as f64);
    let block = (64.0 * 1024.0 * 1024.0f64).min(8.0 * n * m.max(1.0));
    Ok(Part {
        bytes: shape.factor_of_a() + BYTES_PER_DUAL_ENTRY * m * m + block,
        what: "the factor of A and the condensed dual H with the inner solver's copy".into(),
    })
}

/// auto: the members of its chain run one after another ([`crate::backends::auto::chain_for`]);
/// one that does not fit is refused by its own checks and the chain goes on, except after a
/// sparse primal member, whose refusal ends it.  The same walk with the estimates: the run fits
/// when a member fits before the chain would end, and its peak is the largest need among the
/// members that fit up to there; when none fits, the figure is the member that ends the chain
/// (else the smallest need).
pub fn auto(shape: &RunShape<'_>) -> Result<Part, QpError> {
    walk(
        shape,
        &crate::backends::auto::chain_for(shape.qp, shape.coulomb),
    )
}

/// [`auto`]'s walk over `chain` (each member with whether its memory refusal ends the chain).
///
/// # Errors
/// What a member's estimate returns.
pub fn walk(shape: &RunShape<'_>, chain: &[(BackendKind, bool)]) -> Result<Part, QpError> {
    let names: Vec<&str> = chain.iter().map(|(k, _)| k.name()).collect();
    let mut running: Option<(f64, &'static str)> = None;
    let mut refused: Option<(f64, &'static str)> = None;
    for (kind, ends) in chain {
        let part = (kind.entry().need)(shape)?;
        if shape.fits(shape.path.bytes + part.bytes) {
            if running.is_none_or(|(b, _)| part.bytes > b) {
                running = Some((part.bytes, kind.name()));
            }
        } else {
            if running.is_none() && refused.is_none_or(|(b, _)| part.bytes < b || *ends) {
                refused = Some((part.bytes, kind.name()));
            }
            if *ends {
                break;
            }
        }
    }
    let ((bytes, name), how) = match (running, refused) {
        (Some(r), _) => (r, "the largest of the members that fit"),
        (None, Some(r)) => (r, "no member fits"),
        (None, None) => ((0.0, "none"), "no member"),
    };
    Ok(Part {
        bytes,
        what: format!("the chain {}: {how} ({name})", names.join(" → ")),
    })
}
