//! Interior-point backend of signorini over [clarabel](https://clarabel.org).
//!
//! Our contact QP
//!
//! ```text
//! minimise ½ xᵀ A x − fᵀ x   subject to   B x ≤ g
//! ```
//!
//! is handed to clarabel, which solves `min ½ xᵀ P x + qᵀ x  s.t.  A_c x + s = b, s ∈ K`, as
//!
//! ```text
//! P = triu(A)   (clarabel reads the upper triangle only)
//! q = −f
//! A_c = B,  b = g,  K = ℝᵐ₊ (NonnegativeConeT(m); no cone at all when m = 0)
//! ```
//!
//! so s = g − Bx is the slack of each contact row.  clarabel's dual z ∈ K* = ℝᵐ₊ satisfies
//! `P x + q + A_cᵀ z = 0`, i.e. `A x − f + Bᵀ z = 0`: the multipliers are λ = z ≥ 0, the contact
//! forces, with no sign change.
//!
//! Before the hand-over the problem is rescaled with the core's `QpScaling` (A, f, g of order
//! one; `ClarabelSettings::rescale`), because clarabel's absolute gap tolerance is otherwise
//! meaningless for loads of 1e-7 or 1e11; x and λ are scaled back.
//!
//! Status mapping: `Solved` → solved; `AlmostSolved` and `InsufficientProgress` → inaccurate
//! (the core's residual check may still call them solved); `MaxIterations`, `MaxTime` →
//! max-iterations, time-limit; `(Almost)PrimalInfeasible` / `(Almost)DualInfeasible` →
//! primal-/dual-infeasible, with x = 0 and λ = 0 (clarabel then returns a certificate, not a
//! point); `NumericalError`, `Unsolved` → numerical-error.  Non-finite output becomes
//! numerical-error with zeros.
#![forbid(unsafe_code)]

mod backend;
mod settings;

pub use backend::ClarabelBackend;
pub use settings::{ClarabelSettings, ClarabelSettingsError, DirectSolver};

/// The backend's name in reports and on the command line.
pub const NAME: &str = "clarabel";
