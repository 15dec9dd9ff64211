//! Primal–dual active-set QP backend of signorini on the sparse primal KKT system.
//!
//! The contact problem
//!
//! ```text
//! minimise ½ xᵀ A x − fᵀ x   subject to   B x ≤ g
//! ```
//!
//! (A: n × n stiffness, possibly singular for floating bodies with a known kernel R; B: m × n
//! node-to-segment rows) is solved by the primal–dual active-set method of Hintermüller, Ito
//! and Kunisch — a semismooth Newton method on the complementarity function
//! λ − max(0, λ + c (Bx − g)) — as in deal.II's step-41, but with a sparse direct solver:
//!
//! ```text
//! F₀ = every row, or the set an interior-point predictor finds (see "Start" below)
//! repeat:   [ A    B_Fᵀ ] [ x  ]   [ f   ]
//!           [ B_F   0   ] [ λ_F] = [ g_F ],     λᵢ = 0 off F,
//!           F ← { i : λᵢ + c (Bx − g)ᵢ > 0 }
//! ```
//!
//! (continued by an interior-point method when the sets flip, and started by one on a curved
//! interface, see below) until the set
//! reproduces itself and (x, max(λ, 0)) meets the core's KKT residuals
//! ([`signorini_qp::kkt_residuals`]) at the requested tolerance (an answer that meets
//! them while rows still want to change is taken only at a cycle or at the iteration cap).  The status is honest otherwise: a set that repeats without
//! meeting them (`inaccurate`), an interior-point step that cannot move (`inaccurate`), the iteration or time limit,
//! `primal-infeasible` only with a Farkas certificate y ≥ 0, Bᵀy ≈ 0, gᵀy < 0 checked by the
//! core's [`signorini_qp::FarkasRay`] (any feasible x would move at least 10⁸ times the
//! displacement that closes the ray's gaps; y is the last refinement correction of λ, or λ⁺), and
//! `dual-infeasible` only with a rigid motion r = R α that the load drives (fᵀr > 0) and that
//! closes no contact (B r ≤ 0) — found before any factorisation when no row sees a loaded mode,
//! or in the rigid part of a stalled iterate.  A non-finite answer is never handed out.
//!
//! # One symbolic factorisation for every active set
//! [`kkt`](self) builds K = [A + ρI, Bᵀ; B, −D] once with the pattern of **all** m rows: an
//! inactive row keeps its B entries as explicit zeros and gets Dᵢᵢ = 1/s (s the mean diagonal
//! of A), so its equation reads λᵢ = 0; an active row gets its B entries and a static
//! Dᵢᵢ = δ = 10⁻⁸/s.  K is then quasi-definite (A + ρI positive definite, −D negative
//! definite), so an LDLᵀ factorisation without pivoting exists in any symmetric ordering: one
//! fill-reducing ordering ([`signorini_qp::linalg::kkt_order`]: AMD of K's node-compressed
//! graph, the same fill as AMD of K found 14–58 % faster; the timing floor orders A by
//! [`signorini_qp::linalg::fill_reducing_order`]) and one symbolic analysis (the project's simplicial one where faer's flop rule picks a
//! simplicial factor, else faer's supernodal one) serve every set; each set costs one numeric
//! LDLᵀ (with dynamic regularisation of any pivot below 10⁻³ of the static ones as a safety
//! net).  ρ = 10⁻¹⁰ s is added only when A has a
//! kernel, so that K exists while the active rows do not yet hold every rigid mode.  The
//! ordering reads K's graph straight off A and B, and K is built in that order and in the
//! triangle the numeric kernel reads, so the analysis carries no permutation and no
//! factorisation copies K into order (faer's permuted path does, on every call: a quarter of
//! each numeric factorisation on the partial strip); the solves permute their right-hand
//! sides instead.
//!
//! # Accuracy: refinement against the unregularised system
//! δ and ρ perturb the system, and the factor of a very ill-conditioned K (a strip 1000 times
//! longer than thick) carries round-off.  [`refine`](self) therefore iterates
//! z ← z + K̃⁻¹ (b − K z) with K̃ the regularised factor and K the **exact** KKT matrix applied
//! through the sparse A and B, until the scaled residual max(‖r_x‖∞ / F, |r_λ,ᵢ| / Xᵢ) is
//! 10⁻³ × tol, within 4× the round-off of forming it, or stops decreasing.  Refinement runs
//! only for a set that predicts itself (the unrefined solution of a set that is about to change
//! is accurate enough to choose the next set).  Measured: one or two steps reach 10⁻¹²–10⁻¹³
//! stationarity on the 51 575-DOF strip, where dual-ssn (dense condensed Hessian) settles
//! on an inaccurate answer.
//!
//! # Few factorisations: start set and low-rank updates
//! *Start.*  Active-set iterations (one LDLᵀ or update each) by first set, tol 1e-9:
//!
//! | scene | m | every row ([`StartSet::All`], the default's choice here) | closed gaps | empty (textbook) |
//! |---|---|---|---|---|
//! | strip-floating (51 575 DOFs) | 2001 | **1** | 1 | 2 |
//! | strip-clamped (51 572 DOFs) | 2001 | **2** | 2 | 2 |
//! | hard/chain-four | 25 | **1** | 1 | 5 |
//! | hard/inclined | 11 | **2** | 2 | 3 |
//! | hard/gap-closes | 6 | **4** | 5 | 5 |
//! | hard/nonconforming-10to1 | 51 | **7** | 7 | 8 |
//! | seed/exp1, exp2b | 6 | **4** | 4 | 5 |
//! | seed/exp3-both-h0.08 | 14 | **5** | 5 | 6 |
//! | seed/exp6a | 17 | **5** | 5 | 7 |
//! | seed/exp7 | 4 | **2** | 2 | 3 |
//!
//! A warm start ([`signorini_qp::SolveOptions::warm_start`]: a load path's previous increment)
//! overrides the setting: the first set is the one the given answer predicts (measured on the
//! Cattaneo path of BENCHMARKS.md: 26 active-set steps over its 3 increments become 22; started
//! from its own answer, a problem settles in one step).
//!
//! Starting with every row active is never worse than the others here: the textbook empty
//! start costs one to four more steps (its first step only finds the unconstrained answer),
//! and the closed-gap start ties except on gap-closes.  A long interface pressed along its
//! whole length (all rows end active) then takes one factorisation and refinement, and a
//! floating body has every rigid mode held from the first factorisation; rows with an open
//! gap that should not touch carry tension after the first solve and leave the set.
//! (Counts measured with the `start` setting varied, same build otherwise.)
//!
//! Every scene of that table is a flush interface: its rows touch at once.  On a curved one
//! (a cylinder on a block) every row glues open gaps as well, the first solve puts most rows
//! in tension, and the iteration hands over to its interior-point phase from that glued
//! answer.  [`StartSet::Interior`] starts there instead, from the centred point (x = 0, every
//! gap and multiplier shifted into the interior), and solves the set its first predictor step
//! finds; the default [`StartSet::Auto`] takes it where fewer than half the rows touch first
//! ([`signorini_qp::first_touch`]), every row elsewhere.  `signorini solve SCENE --backend pdas`
//! (iterations: factorisations + low-rank updates), every row → interior start:
//!
//! | scene | m (active) | touch first | every row | interior start |
//! |---|---|---|---|---|
//! | accuracy/hertz | 311 (94) | 5 | 14: 9 + 5 | **8: 3 + 5** |
//! | accuracy/hertz-graded | 160 (50) | 2 | 13: 8 + 5 | **6: 3 + 3** |
//! | hard/strip-thin-partial (flush) | 2 001 (403) | 2 001 | **3: 3 + 0** | 3: 2 + 1 |
//! | hard/strip-thin-floating (flush, all active) | 301 (301) | 301 | **1: 1 + 0** | 2: 2 + 0 |
//!
//! A flush interface keeps every row: pressed along its whole length it is solved by the
//! first factorisation, which the interior start would follow with a second; only where the
//! load lifts most of it (the partial strip) would the interior start save one.  No other
//! fixture of `fixtures/hard`, `accuracy` or `seed` changes its iterations.
//!
//! *Updates.*  When a set differs from the factored one in k rows (say the one row at a
//! clamped end that lifts off, or the few rows a Hertz contact zone gains or loses per step),
//! [`update`](self) solves with the new K through the old factor by block elimination: one
//! solve per changed row (batched into one supernodal sweep, and kept until the next
//! factorisation, so a row that stays changed costs one solve in all), a k × k dense system,
//! and per later solve a correction of O((n + m) k); exact up to round-off and refined like any
//! other solve.  It is used when the missing columns plus the iteration's solves are measured
//! to cost less than a factorisation, k ≤ [`PdasSettings::max_update_rank`], and the kept
//! columns take no more memory than the factor (nor half the free memory).  A set that settles
//! short of the tolerance, or a cycle that shows, through an update is factorised once more
//! before it is judged, so an update never makes a status worse than `solved`, which the
//! residuals against the exact A and B decide.
//!
//! # Measured
//! Release build on the 2-core machine shared with other helpers (load average ~2 during these
//! runs, 13:36 UTC; `signorini compare SCENE --backends clarabel,dual-ssn,pdas --time-limit 60`,
//! three runs each for the first four rows, one for the rest).  The floor is compare's: one
//! factorisation + solve of A.
//!
//! | scene | DOFs | m | pdas ÷floor | pdas steps | clarabel ÷floor | dual-ssn |
//! |---|---|---|---|---|---|---|
//! | strip-floating (20 × 0.02, hmax 0.01) | 51 575 | 2001 | 1.52, 1.49, 1.51 | 1 factorisation | 13.1, 12.9, 13.1 | inaccurate, 64× |
//! | strip-clamped | 51 572 | 2001 | 1.68, 1.73, 1.79 | 1 factorisation + rank-1 update | 16.6, 16.8, 17.0 | inaccurate, 67× |
//! | seed/exp2b | 448 | 6 | 2.42, 2.39, 2.19 | 4 (1 factorisation + 3 updates) | 9.9, 9.9, 9.8 | 2.6, 2.4, 2.2× |
//! | seed/exp3-both-h0.08 | 2 124 | 14 | 1.99, 2.03, 1.96 | 5 (1 + 4 updates) | 11.2, 11.0, 11.0 | 1.6, 1.6, 1.5× |
//! | strip-floating 80 × 0.02 | 206 237 | 8001 | 1.55 | 1 factorisation | – | max-iterations, 195× |
//! | strip-clamped 80 × 0.02 | 206 234 | 8001 | 1.73 | 1 factorisation + rank-1 update | – | max-iterations, 230× |
//! | strip-floating 200 × 0.02 | 515 577 | 20 001 | 1.58 | 1 factorisation (nnz(L) 8.8e6) | – | – |
//! | exp2b at hmax 0.02 | 30 002 | 51 | 4.14 | 8 (2 + 6 updates) | – | 1.81× |
//! | exp2b at hmax 0.005 | 461 680 | 201 | 4.16 | 9 (5 + 4 updates) | – | 1.35× |
//!
//! The clamped 200 × 0.02 strip has no floor at all: compare's Cholesky of A alone breaks down
//! (a pivot vanishes; A is that ill-conditioned), while pdas solves it (`signorini solve …
//! --backend pdas`: 20 000 rows active, stationarity 1.4e-11, 1 factorisation + a rank-1 update).
//!
//! On a long interface pdas is the fastest solver that meets the tolerance, well inside 2× the
//! floor; its residuals (stationarity ~1e-12) are as good as clarabel's.  On Hertz-like scenes
//! with few rows the PDAS needs 4–9 active-set steps, like dual-ssn, and each step that is not
//! an update is a factorisation of the whole K: there the condensed dual (dual-ssn, dual-pgs)
//! is 2–3× faster.  Outside the numeric factorisation most time goes to the ordering and the
//! symbolic analysis of K, which the floor pays for A.  Where the rest of the gap to the floor
//! comes from (`crates/scene-tests/tests/pdas_measure.rs`, one process, medians of five, 51 575-DOF strip): K's factor holds
//! 8.8e5 entries against A's 5.6e5 (the contact rows couple the two bodies, which A alone does
//! not), and faer's simplicial LDLᵀ takes ~1.7× its LLᵀ on the same pattern (20 ms against
//! 12 ms on A); faer's supernodal variant factors K slightly faster but solves 8× slower, so
//! faer's own choice (simplicial here) is kept.  Since issue 21 a simplicial factor of K is
//! the project's own (`signorini_qp::linalg::ldlt`: the pattern of every row of L found once,
//! a node's two displacements eliminated in one pass), which factors the 2 001-row partial
//! strip's K in 0.11 of the floor's time against faer's 0.25 (BENCHMARKS.md, "pdas's own
//! simplicial LDLᵀ").  Every seed and hard fixture is solved
//! and agrees with clarabel (max |Δu| ≤ 3e-10 at displacements ~0.2); hard/floating-free is
//! `dual-infeasible`, as for every backend.
//!
//! # When the sets flip: interior-point continuation and crossover
//! Plain PDAS converges for M-matrix-like problems; the contact Schur complement of a thin
//! strip loaded on part of its length is not one (releasing a row at the edge of the contact
//! zone lifts the strip far away).  On strip-partial (the 51 575-DOF strip, traction on
//! [8, 12] only, 403 rows active at the solution) the plain steps flip 40–60 rows a step
//! around ~650 active rows, with far-away patches of rows that carry no force but keep the
//! strip from lifting, and end at `max-iterations` after 100 steps (KKT residuals ~1e-2).
//!
//! The iteration therefore watches itself: when a set comes back, or (from the sixth step on,
//! `MIN_PLAIN_STEPS`, so that no seed or hard fixture is handed over) a step changes at least
//! as many rows as the step two before, it hands over (`active_set::interior`) to a
//! primal–dual interior-point method (Mehrotra's predictor–corrector) on the **same** KKT
//! pattern — every row present with −D, D = diag(s/λ), one numeric LDLᵀ of the one symbolic
//! factor per step — whose iterate moves every row's status a little at a time, so a non-local
//! change cannot make it flip.  Once μ has fallen tenfold and the set the iterate predicts,
//! { i : λᵢ Xᵢ > sᵢ F } (force and gap in the units of the KKT residuals), is the same twice
//! in a row — and once right after the first interior step (issue 21: on the long
//! partial-contact strips that set is the answer's or a few rows off) — that set is solved
//! exactly (factorised, refined against the unregularised system) and plain active-set steps
//! follow from it, through low-rank updates of that factor while few rows change, until they
//! would hand over again; the answer is accepted only on a set that reproduces itself and
//! meets the tolerance, as before.  These
//! exact solves use ρ = 0 even for a floating body: with ρ = 10⁻¹⁰ s the crossover solve of
//! the right set on strip-partial stalled in refinement at a penetration of 0.17 (relative),
//! because the strip's bending mode is itself ~10⁻⁹ s soft; the set then holds every rigid
//! mode, and a set that does not is caught by the dynamic regularisation and fails the test.
//!
//! A step that changes more rows than a low-rank update takes ([`PdasSettings::max_update_rank`],
//! 256 by default) hands over at once, from the first step on (issue
//! 21): such a set could not be reached by a low-rank update anyway, and on a long interface
//! it is where the plain steps start to flip (strip-partial's first step, from every row
//! active, drops 689 rows: the oscillating multipliers of the glued strip beyond the load,
//! positive and negative lobes decaying over a few rows and round-off further out, decide
//! the far rows by their signs, and each set released this way pivots the free strip about
//! the rows it keeps).  The interior-point start is the iterate shifted into the interior by
//! 0.1 of each row's length scale and of the force scale (`active_set::interior`); Mehrotra's
//! centring shift, used before, is ≈ 0 at the first step's iterate (every gap closed) and
//! started at the boundary (82 steps).  Factorisations on strip-partial: floating 13 → 5
//! (1 plain step, 2 interior, 2 exact solves), clamped 21 → 9.
//!
//! Measured (release, `signorini compare SCENE --backends clarabel,pdas --time-limit 60`,
//! three runs each (strip-partial: twice three, before and after `MIN_PLAIN_STEPS`), other
//! helpers' builds running, load average 1.4–2.2, 14:10–14:17 UTC;
//! "strip-partial clamped" is strip-partial without `components = ["x"]`):
//!
//! | scene | pdas ÷floor | pdas work | clarabel |
//! |---|---|---|---|
//! | strip-partial (51 575 DOFs, m 2001, 403 active) | 10.5, 11.5, 10.1; 11.2, 9.1, 10.1 (now 3.2, see BENCHMARKS.md) | 14 factorisations: 7 plain steps, 5 interior-point steps, 2 exact solves (now 5) | inaccurate, 45–50× |
//! | strip-partial clamped (51 572 DOFs) | 25.7, 26.9, 22.9 | 33 factorisations: 9 plain, 16 interior-point, 8 exact | – |
//! | strip-floating | 1.82, 1.69, 1.95 | 1 factorisation (unchanged) | 15.6× |
//! | strip-clamped | 1.69, 1.85, 1.88 | 1 factorisation + rank-1 update (unchanged) | 21.1× |
//! | seed/exp2b | 2.21, 2.47, 2.40 | 4 steps (unchanged) | 10.3–10.9× |
//! | seed/exp3-both-h0.08 | 2.47, 2.42, 2.45 | 5 steps (unchanged) | 14.7–15.1× |
//!
//! dual-ssn solves strip-partial in 789 dense active-set steps (27 s, ~800× the floor) and
//! finds the same 403 rows.  Before this continuation pdas ended strip-partial at
//! `max-iterations` (100 steps, 44× the floor).  The 7 plain steps before the hand-over of the
//! table are gone with that rule (handing over as soon as a step fails to halve
//! the changes had cut strip-partial to 11 factorisations but turned 15 fixtures' 4–7 plain
//! steps into 7–13); what remains is one numeric factorisation per interior step and per
//! exact solve, ~4× the floor at m = 2 001 and 20 001 (BENCHMARKS.md) against the issue's
//! goal of 2×.  Also measured on strip-partial and not kept: an active-set rule that ignores
//! forces and penetrations below 0.1 tol (relative) — the far rows' signs are then no longer
//! round-off, but releasing every row beyond the first lobes lets the free strip pivot down
//! about the lobes kept (it penetrates by up to 1e-1 of the lift-off gap) and the sets
//! alternate between ~430 and ~1 600 rows; the plain steps' ρ = 10⁻¹⁰ s bends such a free
//! cantilever visibly (a curved penetration profile where the exact one is straight), ρ = 0
//! straightens it but does not stop the flips.  Every seed and hard fixture takes the
//! same number of steps as before the continuation.
//!
//! Tried first and measured on strip-partial, then removed: (a) a semismooth Newton method on
//! the augmented Lagrangian ½xᵀAx − fᵀx + (1/2c) Σ max(0, λ̄ + c(Bx − g))² with an exact line
//! search (the merit decreased at every step, for c = 10⁻², 1 and 10³ times s, but the sets
//! still changed 20–100 rows a step and 190 steps did not converge); (b) a primal feasible
//! active-set method with the PDAS sets, an exact line search on the energy over feasible points
//! and a ratio test (monotone, cannot cycle, but the edge of the contact zone moves one or
//! two rows per few steps: 1000 steps did not converge).  Earlier, a backtracking line search
//! on the complementarity residual and a "worst rows only" rule had not helped either.
//!
//! # Friction: box rows and Coulomb
//! A box row |λᵢ| ≤ sᵢ (Tresca, [`signorini_qp::ConstraintBlock::Box`]) has three states, chosen
//! by vᵢ = λᵢ + c (Bx − g)ᵢ: stick (|vᵢ| ≤ sᵢ: active, B x = g on it), or slip at sᵢ sign vᵢ
//! (inactive, λᵢ fixed on the right-hand side) — the semismooth Newton step of
//! λ = P_[−s, s](λ + c r) (Hüeber, Stadler and Wohlmuth).  For Coulomb rows
//! ([`QpBackend::solve_coulomb`](signorini_qp::QpBackend::solve_coulomb)) the bound is
//! μ max(0, vₙ) of the row's normal row, and a slipping row's multiplier is tied to its normal
//! row's, λₜ = ±μ λₙ: the KKT system of the set gains the unsymmetric columns ±μ B_tᵀ on the
//! normal rows, solved with the symmetric factor and GMRES on the tied normal forces
//! (`coupling`).  Sets with box rows do not hand over to the interior-point continuation (it
//! knows one-sided rows only): their plain steps go on until the set settles, repeats
//! (`inaccurate`) or the cap.  Measured (`signorini compare`, 2026-11-26): the Coulomb strip of
//! BENCHMARKS.md ("Friction", 2 001 normal rows) in 2 steps, 1.9× the floor, where the fixed
//! point over Tresca solves takes 17 steps and 17.8×.
//!
//! # Layout
//! `settings` — [`PdasSettings`]; `kkt` — K's fixed pattern and its values for a set;
//! `factor` — ordering, symbolic analysis, numeric LDLᵀ, solves; `update` — solves for a set
//! near the factored one; `refine` — one set's refined solution; `kernel` — rigid modes and the
//! dual-infeasibility certificate; `dense` — a small LU; `active_set` — the iteration and its
//! stopping tests; `active_set::interior` — the interior-point continuation and the crossover;
//! `coupling` — Coulomb's slipping rows tied to their normal rows; `backend` — the
//! [`QpBackend`](signorini_qp::QpBackend).
//! The memory of the factor (its values and faer's workspace, from the symbolic factor) is
//! checked with [`signorini_qp::memory::check_fits`] before the numeric factorisation; a
//! factor that does not fit gives `QpError::TooLarge`.

mod active_set;
mod backend;
mod coupling;
mod dense;
mod error;
mod factor;
mod kernel;
mod kkt;
mod memory;
mod refine;
mod settings;
mod update;

pub use backend::PdasBackend;

/// The KKT matrix and its factor, for the hand-run timing breakdown of
/// `crates/scene-tests/tests/pdas_measure.rs`; not part of the API.
#[doc(hidden)]
pub mod internals {
    pub use crate::factor::KktFactor;
    pub use crate::kkt::KktMatrix;
}
pub use error::PdasError;
pub use memory::{memory_need, PdasNeed};
pub use settings::{PdasSettings, StartSet};
