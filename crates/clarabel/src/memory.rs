//! What clarabel will allocate, estimated before it runs (see
//! [`signorini_qp::memory::KktEstimate`]).
//!
//! clarabel factors the quasidefinite KKT matrix [P + εI, Aᵀ; A, −(W² + εI)] (n + m, P = triu of
//! our A, A = B, W diagonal for the nonnegative cone) by LDLᵀ, after an AMD ordering: qdldl
//! (`Lx`, `Li`: 16 B per nonzero of L) or faer's supernodal LDLᵀ (8 B per stored value plus
//! fewer indices), chosen by `direct_solve_method`.  Besides the factor it keeps the assembled
//! K and its permuted copy (with the map from P and A into it), its own equilibrated copies of
//! P and A, and some forty vectors of n + m (iterates, residuals, step directions, the cone's
//! scaling, the refinement work vectors).  On our side of the hand-over the rescaled problem
//! ([`signorini_qp::QpScaling`]) and the CSC parts handed over are two more copies of A
//! and B.

use signorini_qp::memory::{KktEstimate, KktModel};
use signorini_qp::{QpError, QpProblem};

use crate::NAME;

/// clarabel's memory, in the units of [`KktModel`] (see the module documentation).
///
/// Compared once with a measurement (release build, `/usr/bin/time -v`, 2026-11-26): on
/// `fixtures/seed/exp3-both-h0.08.toml` at `hmax = 0.019` (33 108 DOFs, 54 rows; K of size
/// 33 162, nnz(L) = 1.98e6) the estimate is 83.8 MiB; the whole
/// `signorini solve --backend clarabel` peaked at 83.1 MiB resident, of which 41.1 MiB are
/// what `signorini check` alone reaches (mesh, assembly, the analyses).  So the model is about
/// twice clarabel's own increment (~42 MiB) and about the whole run's peak: conservative, as a
/// refusal must be.  (OSQP on the same scene: estimate 133 MiB, peak 113.4 MiB, increment
/// ~72 MiB; BENCHMARKS.md "Memory guards of every backend".)
pub const MEMORY_MODEL: KktModel = KktModel {
    factors: 1.0,
    bytes_per_value: 16.0,
    kkt_copies: 2.0,
    data_copies: 4.0,
    vectors: 40.0,
};

/// The memory clarabel needs for `problem` (the same for the rescaled problem: the pattern is
/// the same), from the symbolic analysis of its KKT pattern.
///
/// # Errors
/// [`QpError::TooLarge`] when even the analysis does not fit, [`QpError::Backend`] when it fails.
pub fn memory_need(problem: &QpProblem) -> Result<KktEstimate, QpError> {
    KktEstimate::of(NAME, problem, &MEMORY_MODEL)
}
