//! Hand-written dual QP backend of signorini.
//!
//! The contact problem
//!
//! ```text
//! minimise ½ xᵀ A x − fᵀ x   subject to   B x ≤ g
//! ```
//!
//! (A: n × n stiffness, B: m × n contact rows, m ≪ n) is solved through its dual on the contact
//! multipliers λ ≥ 0:
//!
//! ```text
//! minimise ½ λᵀ H λ − λᵀ d   subject to   λ ≥ 0,
//! H = B A⁻¹ Bᵀ (m × m, dense),   d = B A⁻¹ f − g,   and then   x = A⁻¹ (f − Bᵀ λ).
//! ```
//!
//! A is factored once (sparse Cholesky, faer).  Three algorithms work on the dual:
//!
//! * **`dual-pgs`** — projected Gauss–Seidel on the dense H, formed by condensation (multi-RHS
//!   solves H = B (A⁻¹ Bᵀ), or the Schur complement of A on the touched DOFs):
//!   `λᵢ ← max(0, λᵢ − ω (Hλ − d)ᵢ / Hᵢᵢ)`; on a box row (Tresca's tangential multipliers,
//!   |λᵢ| ≤ sᵢ) the projection is onto [−sᵢ, sᵢ], as in dual-uzawa; dual-ssn gives a box row
//!   three states (stick, or slip with λᵢ fixed at ±sᵢ).
//! * **`dual-uzawa`** — projected gradient with one solve per step and no H:
//!   `x = A⁻¹(f − Bᵀλ)`, `λ ← max(0, λ + ρ (Bx − g))`, ρ = 1/L̂ with L̂ ≥ λ_max(H) from power
//!   iteration; by default accelerated (FISTA with gradient restart).
//! * **`dual-ssn`** — primal–dual active set (semismooth Newton): solve the equality-constrained
//!   dual on the current active set, update the set from `λᵢ − νᵢ / Hᵢᵢ > 0` with the exact dual
//!   gradient ν = g − B x; exact once the set settles.  Every Newton step is refined against the
//!   primal residual computed with the sparse A and B (see below), and the Newton system is
//!   solved with the dense H or matrix-free (see "No dense cliff").
//!
//! # Layout
//! [`factor`](self) — the one sparse factorisation of A (contact DOFs last) as the generalised
//! inverse A⁺, ordered by the project's one fill-reducing ordering
//! (`signorini_qp::linalg::fill_reducing_order`, the floor's path; the solution message names
//! the ordering and nnz(L)); `hessian/` — the dense H, one file per way of forming it, each
//! checked against the available memory before it allocates; `methods/` — one file per dual
//! method, plus `newton` (the dense and the matrix-free solve of one active set's Newton
//! system); `monitor` — stopping tests and limits shared by the methods; `dual` — the data every
//! method works on (d, x(λ), the accurate x(λ) of the refinement); `backend` — the
//! [`QpBackend`](signorini_qp::QpBackend) that picks a method.  Dependencies run one way:
//! methods → hessian → factor.
//!
//! # Accuracy on ill-conditioned duals (long thin bodies)
//! The dual Hessian of a thin body is very ill-conditioned (a strip held at one point has the
//! compliance of a cantilever), and forming H by condensation loses digits.  `dual-ssn` therefore
//! treats its dense (or matrix-free) Newton solve only as a preconditioner: after each solve it
//! computes x = A⁺(f − Bᵀλ) − Rμ with the sparse factor, the residuals (Bx − g)_F and Rᵀ(f − Bᵀλ),
//! and corrects (λ_F, μ) with the same factored system until the residual stops decreasing.
//! Two details make the last digits reachable: the sparse solve is itself refined with a
//! residual f − Bᵀλ − A x summed in double-double arithmetic (mixed-precision refinement: the
//! forward error of x drops from ε·cond(A) to ε), and λ is carried as an unevaluated sum
//! λ + λ_lo during the refinement, because the dual amplifies the rounding of λ by its
//! condition number.  On the thin strips of issue 9 (51 k DOFs, 2 001 rows, all active)
//! this takes the KKT residuals from 1.2e-3 (dense solve alone) to ~1e-18 in 3–5 corrections.
//!
//! `dual-pgs` tracks the dual objective ½λᵀHλ − dᵀλ = ½λᵀ(w − d) from its maintained gradient
//! w = Hλ − d: with ω ∈ (0, 2) and Hᵢᵢ > 0 every coordinate step lowers it, so a sweep that
//! raises it beyond round-off (relative 1e-12), or a dense objective that disagrees with the one
//! measured through the sparse solve at a full check (relative 1e-6), means the dense H is not
//! the PSD matrix B A⁺ Bᵀ: PGS stops with `numerical-error` ("PGS lost monotonicity …").  When it
//! stalls, or the rate of its best KKT residual over the second half of its sweeps (after 4 000)
//! extrapolates past the iteration limit, it stops with `inaccurate` and says so, instead of
//! running to the limit (the thin strips: after 4 000–7 000 sweeps, ~17 s, instead of 100 000).
//!
//! # No dense cliff
//! Nothing m × m is allocated without asking `signorini_qp::memory::check_fits` first (the
//! dense H with its work arrays, the dense trailing block of the factor, and for `dual-ssn` the
//! dense Newton matrices: ≈ 8·(m² + 3m²) bytes).  The rule:
//!
//! * `dual-ssn` forms the dense H when it fits and m ≤ `DualSettings::matrix_free_rows`
//!   (default 20 000, where H alone is 3.2 GB); otherwise its Newton steps are matrix-free:
//!   projected preconditioned CG on S_FF λ_F = r_F (G_F λ_F = r_e), S applied through the sparse
//!   factor (one forward + one backward triangular solve per product), Jacobi-preconditioned by
//!   the lumped compliance Σⱼ Bᵢⱼ²/Aⱼⱼ, to 1e-8 relative, then refined as above.
//! * `dual-pgs` needs the columns of H: when they do not fit it returns
//!   `Err(QpError::TooLarge)` naming m and the memory, and pointing to dual-ssn, pdas and
//!   dual-uzawa (a resource refusal, exit 3 from `solve`, like a refusal of the factor itself).
//! * `dual-uzawa` never forms H.
//!
//! Measured cross-over (release, 2-core machine shared with other builds; `cargo test -p
//! signorini-dual --release --lib measure_newton_modes -- --ignored --nocapture`): the dense
//! path was faster in every case measured, so the switch is set by memory, not speed:
//!
//! | n | m | rows | dense ssn | matrix-free ssn |
//! |---|---|---|---|---|
//! | 1e4 | 50 | bound | 1.0× floor | 5.3× |
//! | 1e4 | 500 | bound | 11× | 148× |
//! | 1e5 | 50 | 3-DOF | 2.3× | 4.0× |
//! | 1e5 | 500 | 3-DOF | 5.2× | 24× |
//! | 1e5 | 2000 | bound | 25× | 536× |
//! | 1e5 | 2000 | 3-DOF | 14× | 26× |
//!
//! CG needs one sparse solve per product and converges slowly on ill-conditioned duals (the
//! 4 × 0.02 strip of `crates/scene-tests/tests/dual_long_interface.rs`: 14 s matrix-free against 0.3 s dense), so below
//! the memory limit the m solves that form H are cheaper than the CG products of all the Newton
//! steps.  Products are not batched (CG is sequential); a block or deflated CG is the next step.
//!
//! Every method polls the time limit between iterations and inside its long steps (the blocks
//! of multi-right-hand-side solves that form H, the refinement, the CG and power iterations), so
//! it overshoots `SolveOptions::time_limit` by at most one block of solves or one dense
//! factorisation.
//!
//! Every method stops on the core's KKT residuals ([`signorini_qp::kkt_residuals`]) of
//! (x(λ), λ), checked every `check_every` iterations or earlier when a cheap estimate from the
//! dual gradient meets the tolerance.  Limits give `max-iterations` / `time-limit`; a primal
//! without feasible point makes λ grow along a Farkas direction δ ≥ 0 (Bᵀδ = 0, gᵀδ < 0): the
//! growth since the last check is reported as `primal-infeasible` only when the core's
//! [`signorini_qp::FarkasRay`] certifies it against B and g.  A growth with gᵀδ < 0 that
//! is no certificate (a feasible problem whose answer lies far away) lets the method go on, and
//! the message of a run that ends unsolved says why it was no certificate.  The residual scales
//! are computed once per solve ([`signorini_qp::ResidualScales`]).
//!
//! # Floating bodies
//! When A is singular with a known kernel R (`QpProblem::kernel`, n × k), the dual is the
//! FETI one: x = A⁺(f − Bᵀλ) + R α with a generalised inverse A⁺, and the dual gains the
//! equality G λ = e, G = Rᵀ Bᵀ, e = Rᵀ f (the load on each rigid mode must be balanced by the
//! contact forces).  A⁺ = [A_ff⁻¹ 0; 0 0] comes from fixing k DOFs chosen by pivoted
//! Gram–Schmidt on the rows of R (so A_ff stays sparse and positive definite).  The equality is
//! handled by an augmented Lagrangian (PGS, Uzawa: inner bound-constrained problem with
//! H + c GᵀG, multiplier μ updated when the inner residual falls below the equality residual;
//! α = −μ) or directly in the Newton system (active set).  A rigid mode that no contact row sees
//! but the load drives gives `dual-infeasible`; a singular A without (enough) kernel vectors gives
//! `numerical-error` with a message — never NaN.  An unknown with no stiffness at all (a zero
//! column of A: the auxiliary unknowns of Tresca rows written one-sided) that no kernel vector
//! touches is refused at once, before any factorisation (`QpError::Unavailable`, naming why).
//!
//! # Where the time goes (measured, release build, 2-core machine shared with other builds)
//! 5-point Laplacian, n ≈ 1e4 and 1e5, m bound rows (1 DOF each) or 3-DOF rows
//! x_s − ½(x_a + x_b); "floor" = one sparse factorisation + solve of A (faer, AMD).
//!
//! Forming H (max |ΔH| between the variants ≤ 6e-14):
//!
//! | n | m | touched DOFs | factor A + multi-RHS (a) | A_ii + Schur (b) | contact-last factor + L_cc (default) |
//! |---|---|---|---|---|---|
//! | 1e4 | 50 | 50 | 52 ms | 28 ms | 9 ms |
//! | 1e4 | 500 | 1006 | 76 ms | 142 ms | 22 ms |
//! | 1e5 | 50 | 150 | 291 ms | 622 ms | 121 ms |
//! | 1e5 | 500 | 500 | 1515 ms | 1418 ms | 132 ms |
//! | 1e5 | 500 | 1002 | 1497 ms | 2858 ms | 136 ms |
//!
//! Ordering the touched DOFs last costs nothing measurable in the factorisation of these
//! short interfaces and makes H a by-product of it (dense O(|c|² m) work), 10× faster than
//! multi-RHS solves at m = 500.  On a long interface it does not pay: the touched DOFs become
//! one dense separator of |c| ≈ 4m unknowns (the 3 × 0.02 strips of fixtures/hard, m = 301:
//! nnz(L) 2.1e6 instead of 1.6e5, dual-ssn 2.8× slower), so the factor orders them last only
//! when |c|³/3 + |c|² m < 4 m nnz(L) (the dense block's factorisation and H against m
//! solves with the plain factor; `factor::trailing::trailing_pays`); the
//! explicit interior Schur complement (b) only wins when few DOFs are touched and is otherwise
//! slower than (a) (|c| ≈ 2m right-hand sides for node-to-segment-like rows).
//!
//! Whole solves at tol 1e-9 (all `solved`), as multiples of the floor: n = 1e5, m = 500 bound
//! rows: ssn 1.7× (7 active-set steps), pgs 3.3× (3273 sweeps, ~0.1 ms each), uzawa 190×
//! (1440 accelerated steps, one ~13 ms solve each, plus 30 power steps).  n = 1e5, m = 50:
//! pgs 1.4×, ssn 1.6×, uzawa 14×.  Uzawa pays one solve per step by design; it is the method
//! that never forms H.  Numbers from `cargo test -p signorini-dual --release --lib measure --
//! --ignored --nocapture`.

mod backend;
mod dual;
mod error;
mod factor;
mod half_solve_tests;
mod hessian;
mod kernel;
mod measure;
mod methods;
mod monitor;
mod settings;

pub use backend::DualBackend;
pub use error::DualError;
pub use factor::MAX_TRAILING;
pub use settings::{Condensation, DualMethod, DualSettings};
