//! Typed errors of the dual backend.  They never escape as panics: a bad setting becomes a
//! `QpError`, a singular stiffness becomes a `numerical-error` status with the message.

use signorini_qp::linalg::LinalgError;

/// What went wrong while setting up or running the dual method.
#[derive(Debug, thiserror::Error)]
pub enum DualError {
    /// A field of [`crate::DualSettings`] is out of range.
    #[error("invalid dual setting `{field}`: {reason}")]
    Settings {
        /// Field name.
        field: &'static str,
        /// Why it is rejected.
        reason: String,
    },
    /// The stiffness is singular and no kernel basis explains it.
    #[error("stiffness A is singular ({source}); {kernel} kernel vector(s) were given — a body held only by contact needs its rigid-body modes in `QpProblem::kernel`")]
    Singular {
        /// The factorisation's complaint.
        source: LinalgError,
        /// Number of kernel vectors in the problem.
        kernel: usize,
    },
    /// The factorisation went through, but a pivot nearly vanished.
    #[error("stiffness A is numerically singular (smallest pivot ratio L_jj²/A_jj = {ratio:.1e}); {kernel} kernel vector(s) were given — a body held only by contact needs its rigid-body modes in `QpProblem::kernel`")]
    NearlySingular {
        /// minⱼ Lⱼⱼ² / Aⱼⱼ.
        ratio: f64,
        /// Number of kernel vectors in the problem.
        kernel: usize,
    },
    /// A given kernel vector is not in the null space of A.
    #[error("kernel vector {index} is not in the null space of A (‖A r‖∞ / (‖A‖ ‖r‖∞) = {residual:.2e})")]
    NotAKernelVector {
        /// Index of the vector in `QpProblem::kernel`.
        index: usize,
        /// Its relative residual.
        residual: f64,
    },
    /// The kernel vectors are linearly dependent (or zero).
    #[error("the {count} kernel vectors are linearly dependent")]
    DependentKernel {
        /// Number of kernel vectors.
        count: usize,
    },
    /// Another failure of the sparse factorisation.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// A matrix could not be assembled (inconsistent sparse structure).
    #[error("internal matrix assembly failed: {0}")]
    Structure(String),
    /// A refusal the backend hands to its caller as `Err` (memory: `QpError::TooLarge`; a
    /// method that cannot run at this size: `QpError::Unavailable`).
    #[error(transparent)]
    Refused(#[from] signorini_qp::QpError),
    /// The time limit passed inside a long step (forming H, a multi-right-hand-side loop).
    #[error("time limit reached {0}")]
    OutOfTime(String),
    /// A dense factorisation broke down.
    #[error("dense factorisation failed: {0}")]
    Dense(String),
}
