//! What OSQP will allocate, estimated before it runs (see
//! [`signorini_qp::memory::KktEstimate`]).
//!
//! OSQP 0.6 factors the quasidefinite KKT matrix [P + σI, Aᵀ; A, −ρ⁻¹I] (n + m) by qdldl after
//! an AMD ordering: `Lx` and `Li` (c_int is 64-bit), 16 B per nonzero of L.  Polish (on by
//! default) factors a second KKT matrix, [P + δI, A_actᵀ; A_act, −δI] on the active rows — at
//! most as large — while the first factor is kept, so two factors are counted.  OSQP keeps the
//! assembled K and its permuted copy (and those of the polish system), its scaled copies of P and
//! A, and some thirty vectors of n + m (iterates, ADMM variables, residual and scaling vectors,
//! the polish's).  On our side the rescaled problem, the CSC parts and the `osqp` crate's copy
//! handed over are three more copies of A and B.

use signorini_qp::memory::{KktEstimate, KktModel};
use signorini_qp::{QpError, QpProblem};

use crate::NAME;

/// OSQP's memory, in the units of [`KktModel`] (see the module documentation).  Measured once
/// (release build, `/usr/bin/time -v`): on `fixtures/seed/exp3-both-h0.08.toml` at
/// `hmax = 0.019` (33 108 DOFs, 54 rows) the estimate is 133 MiB; the whole
/// `signorini solve --backend osqp` peaked at 113.4 MiB resident, 41.1 MiB of which `signorini
/// check` alone reaches: about twice OSQP's own increment, and above the run's peak
/// (BENCHMARKS.md "Memory guards of every backend").
pub const MEMORY_MODEL: KktModel = KktModel {
    factors: 2.0,
    bytes_per_value: 16.0,
    kkt_copies: 4.0,
    data_copies: 5.0,
    vectors: 30.0,
};

/// The memory OSQP needs for `problem`, from the symbolic analysis of its KKT pattern.
///
/// # Errors
/// [`QpError::TooLarge`] when even the analysis does not fit, [`QpError::Backend`] when it fails.
pub fn memory_need(problem: &QpProblem) -> Result<KktEstimate, QpError> {
    KktEstimate::of(NAME, problem, &MEMORY_MODEL)
}
