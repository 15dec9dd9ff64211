//! What pdas will allocate, estimated before it runs, for the driver's memory guard and
//! `signorini check`.
//!
//! pdas factors the KKT matrix [A, Bᵀ; B, −δI] once per active set.  The estimate comes from
//! the very symbolic analysis the solve runs ([`KktFactor::analyse`]: the same ordering, faer's
//! own count of the factor's values and workspace), so that the figure `check` prints is the one
//! `ActiveSet::new` checks before it allocates ([`setup_bytes`]), plus the dense columns of the
//! factor's inverse that the active-set updates cache ([`PdasNeed::cache`]: never more values
//! than the factor stores, see `ActiveSet`'s column cache).

use signorini_qp::{QpError, QpProblem};

use crate::factor::KktFactor;
use crate::kkt::KktMatrix;

/// What pdas holds at its peak, bytes (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PdasNeed {
    /// Size n + m of K.
    pub dim: usize,
    /// Values of the LDLᵀ factor (faer's count, the simplicial or supernodal kernel's).
    pub nnz_l: usize,
    /// The factor, faer's workspace, K and about ten vectors of n + m ([`setup_bytes`]).
    pub setup: f64,
    /// The cached columns of the factor's inverse: at most as many values as the factor's.
    pub cache: f64,
}

impl PdasNeed {
    /// The total, bytes.
    pub fn total(&self) -> f64 {
        self.setup + self.cache
    }
}

/// The bytes `ActiveSet::new` checks before allocating the factor: the factor and faer's
/// workspace, K (16 B per stored entry) and about ten vectors of length n + m.
pub(crate) fn setup_bytes(factor: &KktFactor, kkt: &KktMatrix) -> f64 {
    let (dim, nnz_k) = (kkt.dim(), kkt.matrix().compute_nnz());
    factor.bytes_needed() + (nnz_k * 16 + dim * 80) as f64
}

/// The memory pdas needs for `problem`, from the symbolic analysis of its KKT pattern (the
/// analysis itself, O(nnz(K)), is not guarded: the driver's guard of the factor of A, which
/// every run passes first, is larger).
///
/// # Errors
/// [`QpError::Backend`] when the analysis fails.
pub fn memory_need(problem: &QpProblem) -> Result<PdasNeed, QpError> {
    let (factor, kkt) = KktFactor::analyse(problem).map_err(|e| QpError::Backend {
        backend: "pdas",
        reason: e.to_string(),
    })?;
    Ok(PdasNeed {
        dim: kkt.dim(),
        nnz_l: factor.nnz_l(),
        setup: setup_bytes(&factor, &kkt),
        cache: 8.0 * factor.nnz_l() as f64,
    })
}
