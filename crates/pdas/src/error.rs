//! Typed errors of the active-set backend.  A bad setting becomes a `QpError`; a failed
//! factorisation becomes a `numerical-error` status with the message, never a panic.

/// What went wrong while setting up or running the active-set method.
#[derive(Debug, thiserror::Error)]
pub enum PdasError {
    /// A field of [`crate::PdasSettings`] is out of range.
    #[error("invalid pdas setting `{field}`: {reason}")]
    Settings {
        /// Field name.
        field: &'static str,
        /// Why it is rejected.
        reason: String,
    },
    /// The ordering or the symbolic analysis of the KKT pattern failed.
    #[error("symbolic analysis of the KKT matrix failed: {0}")]
    Symbolic(String),
    /// The numeric LDLᵀ factorisation broke down (a zero pivot the regularisation did not
    /// catch, or memory).
    #[error("LDLᵀ factorisation of the KKT matrix failed: {0}")]
    Numeric(String),
    /// A given kernel vector is not in the null space of A.
    #[error("kernel vector {index} is not in the null space of A (‖A r‖∞ / (‖A‖ ‖r‖∞) = {residual:.2e})")]
    NotAKernelVector {
        /// Index of the vector in `QpProblem::kernel`.
        index: usize,
        /// Its relative residual.
        residual: f64,
    },
}
