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
//!
//! # Memory
//! Before clarabel allocates anything, the KKT matrix's pattern is analysed symbolically and
//! the factor, clarabel's copies and vectors are priced ([`memory_need`], [`MEMORY_MODEL`]); a
//! run that would not fit in the memory available is refused with `QpError::TooLarge`.  No size
//! is exempt.
//!
//! # Linear solver
//! `ClarabelSettings::direct_solver` picks the LDLᵀ of clarabel's KKT systems: `Qdldl`,
//! `Faer` (this crate's `faer` feature, on by default in the `signorini` driver through its
//! `clarabel-faer` feature) or `Auto` (the default: clarabel computes an AMD ordering and takes
//! faer's supernodal factorisation when the factor is dense enough — flops / nnz(L) ≥ 40 — else
//! qdldl; plain qdldl without the feature).  Measured (release build, 2-core machine shared with
//! other builds; best of three, ratios to the floor of the same run):
//!
//! | scene | n | m | qdldl | faer | auto |
//! |---|---|---|---|---|---|
//! | exp2b | 448 | 6 | 8.9× | 9.0× | 9.3× |
//! | exp3-both-h0.08 | 2 124 | 14 | 21.5× | 22.5× | 22.3× |
//! | nonconforming-10to1 | 15 226 | 51 | 44.4× | 19.5× | 26.3× |
//! | exp3-both at hmax 0.019 | 33 108 | 54 | 42.5× | 30.8× | 24.2× |
//! | thin strip, clamped | 51 572 | 2 001 | 14.3× | 12.5× | 13.6× |
//! | thin strip, floating | 51 575 | 2 001 | 7.2× | 8.0× | 7.3× |
//! | exp3-both at hmax 0.0075 | 206 278 | 135 | 84× (`inaccurate`, 72 s) | 29.4× (25 s) | 30.9× |
//!
//! Small problems do not care; from 10⁴ DOFs faer is 1.4–2.9× faster, and at 2·10⁵ qdldl's
//! answer misses the tolerance where faer's meets it.  `Auto` follows the faster of the two
//! within the noise, so it stays the default, with the feature on.
#![forbid(unsafe_code)]

mod backend;
mod memory;
mod settings;

pub use backend::ClarabelBackend;
pub use memory::{memory_need, MEMORY_MODEL};
pub use settings::{ClarabelSettings, ClarabelSettingsError, DirectSolver};

/// The backend's name in reports and on the command line.
pub const NAME: &str = "clarabel";
