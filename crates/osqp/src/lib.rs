//! ADMM backend of signorini over [OSQP](https://osqp.org) 0.6 (the C library, built by
//! `osqp-sys` with cmake).
//!
//! Our contact QP
//!
//! ```text
//! minimise ½ xᵀ A x − fᵀ x   subject to   B x ≤ g
//! ```
//!
//! is handed to OSQP, which solves `min ½ xᵀ P x + qᵀ x  s.t.  l ≤ A_o x ≤ u`, as
//!
//! ```text
//! P = triu(A)   (OSQP reads the upper triangle only)
//! q = −f
//! A_o = B,  l = −1e30 (OSQP's −∞),  u = g
//! ```
//!
//! OSQP's dual y satisfies `P x + q + A_oᵀ y = 0` with y > 0 on active upper bounds and y < 0 on
//! active lower bounds; with no finite lower bound, λ = y ≥ 0 are the contact forces, with no
//! sign change.  m = 0 needs nothing special: OSQP 0.6 accepts an empty A_o.
//!
//! Before the hand-over the problem is rescaled with the core's `QpScaling` (A, f, g of order
//! one; `OsqpSettings::rescale`) and the default ε_abs is `tol · ‖f‖∞` of that problem, with
//! ε_rel = 0 (see [`OsqpSettings`]); x and λ are scaled back.
//!
//! ADMM converges slowly on stiffness matrices (cond ~ n²): straight to ε_abs = 1e-9 it does not
//! finish in 50 000 iterations on a 2000-node chain.  With polish on, the backend therefore runs
//! a tolerance continuation: ADMM at ε = 1e-3·‖f‖∞, polish (solve the KKT system of the guessed
//! active set), and only if the core's `kkt_residuals` still miss `tol`, tighten ε 100-fold and
//! continue warm from the polished point, down to the target ε_abs.  Iterations are summed over
//! the stages; the message names the last stage.
//!
//! Status mapping: `Solved` → solved (polished or not: the core's residual check decides);
//! `SolvedInaccurate` → inaccurate; `MaxIterationsReached`, `TimeLimitReached` →
//! max-iterations, time-limit (with the last iterate); `PrimalInfeasible(Inaccurate)`,
//! `DualInfeasible(Inaccurate)` → primal-/dual-infeasible with x = 0, λ = 0 (OSQP then holds a
//! certificate, not a point); `NonConvex` and a failed ρ update → numerical-error.
//! OSQP's time limit covers its solve phase, not the setup (scaling, first factorisation).
//!
//! Memory: before OSQP allocates anything, the KKT matrix's pattern is analysed symbolically and
//! its two factors (ADMM's and the polish's), OSQP's copies and vectors are priced
//! ([`memory_need`], [`MEMORY_MODEL`]); a run that would not fit in the memory available is
//! refused with `QpError::TooLarge`.  No size is exempt.
#![forbid(unsafe_code)]

mod backend;
mod memory;
mod settings;

pub use backend::OsqpBackend;
pub use memory::{memory_need, MEMORY_MODEL};
pub use settings::{OsqpSettings, OsqpSettingsError};

/// The backend's name in reports and on the command line.
pub const NAME: &str = "osqp";
