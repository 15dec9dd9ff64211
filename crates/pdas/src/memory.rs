//! What pdas will allocate, estimated before it runs (see
//! [`signorini_qp::memory::KktEstimate`]), for `signorini check`.
//!
//! pdas factors the KKT matrix [A, Bᵀ; B, −δI] once per active set: one LDLᵀ factor at 8 B per
//! value, K (16 B per entry) and about ten vectors of n + m.  These are the terms pdas checks
//! itself before it allocates (`ActiveSet::new`, from faer's own count of the factor); the
//! estimate here prices the factor on nnz(L) of an AMD analysis (faer's supernodal factor may
//! store some more values).

use signorini_qp::memory::{KktEstimate, KktModel};
use signorini_qp::{QpError, QpProblem};

/// pdas's memory, in the units of [`KktModel`] (see the module documentation).
pub const MEMORY_MODEL: KktModel = KktModel {
    factors: 1.0,
    bytes_per_value: 8.0,
    // 16 B per entry of K, in the model's unit of 24 B per entry.
    kkt_copies: 16.0 / 24.0,
    data_copies: 0.0,
    vectors: 10.0,
};

/// The memory pdas needs for `problem`, from the symbolic analysis of its KKT pattern.
///
/// # Errors
/// [`QpError::TooLarge`] when even the analysis does not fit, [`QpError::Backend`] when it fails.
pub fn memory_need(problem: &QpProblem) -> Result<KktEstimate, QpError> {
    KktEstimate::of("pdas", problem, &MEMORY_MODEL)
}
