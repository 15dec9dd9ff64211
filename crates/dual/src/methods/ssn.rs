//! Primal–dual active set (a semismooth Newton method on min(λ, ν/σ) = 0) on the dual:
//!
//! ```text
//! F = { i : λᵢ − νᵢ / Hᵢᵢ > 0 },   λ_Z = 0,
//! [ H_FF  G_Fᵀ ] [ λ_F ]   [ d_F ]
//! [ G_F    0   ] [  μ  ] = [  e  ],    ν = H λ − d + Gᵀ μ = g − B x,
//! ```
//!
//! repeated until F no longer changes.  Each step costs one dense factorisation of order
//! |F| (+ k) ([`super::newton`]).
//!
//! # Refinement against the primal residual
//! The dense H of a thin body is very ill-conditioned (a strip fixed at one point has the
//! compliance of a cantilever), and forming it by condensation loses digits, so the solution of
//! the dense system alone can miss the tolerance by orders of magnitude.  The settled set's step
//! is therefore refined against the exact residual computed with the sparse A and B (while the
//! set still moves, the dense step alone decides the next set — no sparse solve): with
//! x = A⁺(f − Bᵀλ) − R μ (one sparse solve),
//!
//! ```text
//! r_F = (B x − g)_F = d_F − H_FF λ_F − G_Fᵀ μ,     r_e = e − G λ = Rᵀ(f − Bᵀλ),
//! ```
//!
//! (r_e measured on the stored A at x, [`crate::kernel::RigidModes::measured_residual`]: the
//! stored A holds R in its kernel only to round-off, which a large rigid motion amplifies),
//!
//! and (λ_F, μ) is corrected by the already factored dense system applied to (r_F, r_e), until
//! the (scaled) residual stops decreasing: first with plain sparse solves, and only when those
//! miss the tolerance again with solves corrected in double-double arithmetic.  The dense factor only has to be a good
//! preconditioner; the accuracy comes from the sparse residual.  The next active set is decided
//! from the refined λ and the exact dual gradient ν = g − B x.

use std::collections::HashSet;

use signorini_qp::QpStatus;

use super::intervals;
use super::newton::{lumped_compliance, DenseBlock, MatrixFreeBlock};
use crate::dual::{DualData, Outcome};
use crate::error::DualError;
use crate::hessian::{dense_bytes, dual_hessian, DenseSym};
use crate::monitor::{finish_at_limit, Monitor, Next};
use crate::settings::DualSettings;

mod budget;
mod stall;
mod step;

use budget::CheckBudget;
use stall::Stall;
use step::{dense_step, refined_step, Step};

/// From this many active-set steps on, an iterate whose set still moves is checked against
/// the tolerance (one sparse solve) before the next step, once the steps have paid for the
/// check ([`budget`]): the set can move on round-off alone.
const CHECK_MOVING_FROM: usize = 3;

/// Runs the active-set method until the set repeats or the monitor stops it.
pub fn solve(
    data: &mut DualData<'_>,
    settings: &DualSettings,
    monitor: &mut Monitor<'_>,
) -> Result<Outcome, DualError> {
    data.penalty = 0.0;
    // A rigid motion against friction is bounded by the slip work, which the direction test
    // does not weigh: no early certificate with box rows.
    let has_box = signorini_qp::row_sets(&data.problem.blocks)
        .any(|s| matches!(s, signorini_qp::RowSet::Box(_)));
    if let Some(message) = data.modes.farkas_direction().filter(|_| !has_box) {
        return Ok(stopped(data, QpStatus::DualInfeasible, message));
    }
    let newton = Newton::new(data, settings, monitor)?;
    let mut state = State::start(data, &newton);
    loop {
        if let Some((status, message)) = monitor.limit(state.iter) {
            return Ok(finish_at_limit(
                data,
                monitor,
                state.iter,
                state.lambda,
                status,
                message,
            ));
        }
        state.seen.insert(codes(&state.active, &state.fixed));
        let step = loop {
            if let Some(step) = newton.step(data, monitor, &state) {
                break step;
            }
            // A set whose slipping rows leave a rigid mode unheld (every tangential row of a
            // body held sideways by friction alone predicted to slip) has a singular system:
            // the least excessive slip sticks instead, until the modes are held.
            if !state.stick_least_slip() {
                return Ok(newton.singular(data, &state));
            }
        };
        if let Some(outcome) = newton.advance(data, monitor, &mut state, step) {
            return Ok(outcome);
        }
    }
}

/// What the iteration keeps fixed: the dense H (when it is formed), the dual load d, the
/// diagonal that scales the set rule, and how the steps are solved.
struct Newton {
    /// H, when it fits and m ≤ `matrix_free_rows`; else the steps are matrix-free.
    hessian: Option<DenseSym>,
    /// d.
    load: Vec<f64>,
    /// Hᵢᵢ (or the lumped compliance without H): the scale of the set rule.
    diagonal: Vec<f64>,
    /// How the steps are solved, for the message.
    mode: &'static str,
    /// Per row, the bound s of a box row (friction's tangential rows), `None` for a one-sided
    /// row: a box row sticks (active) or slips with λ fixed at ±s (inactive); a zero-bound
    /// row always slips with λ = 0.
    bounds: Vec<Option<f64>>,
    /// Per row, the interval of λ ([`intervals::of`]): what the answer is projected onto.
    sets: Vec<(f64, f64)>,
    /// Flops of one check of a moving set's iterate ([`CheckBudget::check_flops`]).
    check_flops: f64,
}

/// The iteration's state, carried from one step to the next.
struct State {
    /// The current set F.
    active: Vec<bool>,
    /// The multipliers of the inactive rows: 0, or ±s on a slipping box row.
    fixed: Vec<f64>,
    /// Per slipping box row, how far the set rule's vᵢ lies beyond its bound, (|vᵢ| − sᵢ) / sᵢ
    /// (infinite elsewhere): which slip sticks first when the set leaves a rigid mode unheld.
    excess: Vec<f64>,
    /// The sets stepped from so far, with their fixed multipliers' signs (one that comes back
    /// is a cycle); only the refined steps' once they take over ([`State::leave_dense_phase`]).
    seen: HashSet<Vec<i8>>,
    /// λ of the last step.
    lambda: Vec<f64>,
    /// Active-set steps counted so far.
    iter: usize,
    /// Refinement solves so far.
    refinements: usize,
    /// Progress of a set that still moves.
    stall: Stall,
    /// Cheap steps while the set moves (dense: the dense step alone, no sparse solve;
    /// matrix-free: plain sparse solves in the refinement); once it settles, the same set is
    /// solved again, refined with the mixed-precision solves, and decided anew.
    dense_phase: bool,
    /// Refine with the mixed-precision sparse solves.
    accurate: bool,
    /// The next step solves the same set again (not counted as a step).
    redo: bool,
    /// What the steps so far have paid for the checks of a moving set.
    budget: CheckBudget,
}

impl State {
    /// The first set: every row for a floating body, else the rows with dᵢ > 0 and the box
    /// rows (stuck); never a zero-bound box row (its λ is 0 whatever the set).
    fn start(data: &DualData<'_>, newton: &Newton) -> Self {
        let m = data.rows();
        let active = newton
            .load
            .iter()
            .zip(&newton.bounds)
            .map(|(d, b)| match b {
                Some(s) => *s > 0.0,
                None => data.floating() || *d > 0.0,
            })
            .collect();
        Self {
            active,
            fixed: vec![0.0; m],
            excess: vec![f64::INFINITY; m],
            seen: HashSet::new(),
            lambda: vec![0.0; m],
            iter: 0,
            refinements: 0,
            stall: Stall::default(),
            dense_phase: newton.hessian.is_some(),
            accurate: false,
            redo: false,
            budget: CheckBudget::new(newton.check_flops),
        }
    }

    /// Sticks the slipping box row with the least excess ([`State::excess`]); false when no
    /// row slips.  The set so made is recorded as seen, so that a rule that keeps returning to
    /// the singular set ends as a cycle, not a loop.
    fn stick_least_slip(&mut self) -> bool {
        let least = (0..self.active.len())
            .filter(|&i| !self.active[i] && self.fixed[i] != 0.0)
            .min_by(|&a, &b| self.excess[a].total_cmp(&self.excess[b]));
        let Some(i) = least else {
            return false;
        };
        self.active[i] = true;
        self.fixed[i] = 0.0;
        self.excess[i] = f64::INFINITY;
        self.seen.insert(codes(&self.active, &self.fixed));
        true
    }

    /// From now on the sets are decided by the exact dual gradient (refined steps).  The sets
    /// the dense steps visited were decided by the dense H, whose round-off can be far larger
    /// than the answer (A's pivot ratio 3e-11 on a 100 × 0.05 floating strip: the first dense
    /// step on every row gives λ down to −3.7 where the answer's are all ≥ 0.47): the
    /// refined steps going back to one of them is no cycle of the exact rule, so they are
    /// forgotten.  Without this, a refined step that returned to the right set (every row, the
    /// dense phase's first) was taken for a cycle and the set given up.
    fn leave_dense_phase(&mut self) {
        if self.dense_phase {
            self.seen.clear();
        }
        self.dense_phase = false;
    }
}

impl Newton {
    /// Forms H when it fits (besides H: the dense Newton matrix, its shifted copy and their
    /// factor) and m ≤ `matrix_free_rows`.
    fn new(
        data: &DualData<'_>,
        settings: &DualSettings,
        monitor: &Monitor<'_>,
    ) -> Result<Self, DualError> {
        let m = data.rows();
        let fits = signorini_qp::memory::check_fits(
            "dual-ssn",
            String::new,
            dense_bytes(data, settings, 3.0),
        )
        .is_ok();
        let hessian = if fits && m <= settings.matrix_free_rows {
            Some(dual_hessian(data, settings, 3.0, &|| {
                monitor.out_of_time()
            })?)
        } else {
            None
        };
        let load = data.dual_load();
        let diagonal: Vec<f64> = match &hessian {
            Some(h) => (0..m).map(|i| h.diag(i).max(f64::MIN_POSITIVE)).collect(),
            None => lumped_compliance(data),
        };
        let bounds = intervals::box_bounds(data.problem);
        let sets = intervals::of(data.problem);
        let check_flops = CheckBudget::check_flops(
            data.inverse.factor().factor_entries(),
            data.inverse.contact_last(),
            data.problem.stiffness.nnz(),
            data.problem.constraints.nnz(),
        );
        let mode = if hessian.is_some() {
            "dense Newton steps"
        } else {
            "matrix-free Newton steps (projected CG through the sparse factor)"
        };
        Ok(Self {
            hessian,
            load,
            diagonal,
            mode,
            bounds,
            sets,
            check_flops,
        })
    }

    /// The Newton step on the current set: while the set moves, the dense step alone, its
    /// gradient from the dense H (no sparse solve); the settled set (or every set without H)
    /// refined against the primal residual.  `None` when the system is singular.
    fn step(&self, data: &DualData<'_>, monitor: &Monitor<'_>, state: &State) -> Option<Step> {
        let out_of_time = || monitor.out_of_time();
        match &self.hessian {
            Some(h) if state.dense_phase => {
                let block = DenseBlock::factor(h, &data.modes, &state.active);
                dense_step(h, &block, data, &self.load, &state.fixed)
            }
            Some(h) => {
                let block = DenseBlock::factor(h, &data.modes, &state.active);
                // The slipping rows' known forces H_FI λ_I on the right-hand side.
                let known = h.mul(&state.fixed);
                let load: Vec<f64> = self.load.iter().zip(&known).map(|(d, k)| d - k).collect();
                refined_step(
                    data,
                    &block.rows,
                    &|r, e| block.solve(r, e),
                    &load,
                    monitor,
                    (state.accurate, &state.fixed),
                )
            }
            None => MatrixFreeBlock::new(data, &state.active, &self.diagonal, &out_of_time)
                .and_then(|block| {
                    refined_step(
                        data,
                        &block.rows,
                        &|r, e| block.solve(r, e),
                        &self.load,
                        monitor,
                        (state.accurate, &state.fixed),
                    )
                }),
        }
    }

    /// The answer when the current set's system is singular.
    fn singular(&self, data: &DualData<'_>, state: &State) -> Outcome {
        let mut out = stopped(
            data,
            QpStatus::NumericalError,
            format!(
                "singular active-set system on {} rows (redundant contact rows, or a rigid mode the active contacts do not hold; k = {})",
                state.active.iter().filter(|a| **a).count(),
                data.modes.count()
            ),
        );
        out.iterations = state.iter;
        out
    }

    /// Takes the step and decides: the same set again (refined), an answer, or the next set.
    fn advance(
        &self,
        data: &mut DualData<'_>,
        monitor: &mut Monitor<'_>,
        state: &mut State,
        step: Step,
    ) -> Option<Outcome> {
        state.refinements += step.refinements;
        state
            .budget
            .earn(self.step_flops(data, state, step.refinements));
        let (contraction, step_residual) = (step.contraction, step.residual);
        state.lambda = step.lambda;
        data.multiplier = step.mu;
        if !state.redo {
            state.iter += 1;
        }
        state.redo = false;
        // vᵢ = λᵢ − νᵢ / Hᵢᵢ = λᵢ + (B x − g)ᵢ / Hᵢᵢ: a one-sided row is active when vᵢ > 0; a
        // box row sticks when |vᵢ| ≤ sᵢ and slips at sᵢ sign vᵢ otherwise (the semismooth
        // Newton step of λ = P_[−s, s](λ + c r)).
        let mut next_fixed = vec![0.0; data.rows()];
        let mut excess = vec![f64::INFINITY; data.rows()];
        let next_active: Vec<bool> = (0..data.rows())
            .map(|i| {
                let v = state.lambda[i] - step.gradient[i] / self.diagonal[i];
                match self.bounds[i] {
                    None => v > 0.0,
                    // A zero bound: λ = 0, never stuck (a stuck row's λ is unconstrained).
                    Some(0.0) => false,
                    Some(s) if v.abs() <= s => true,
                    Some(s) => {
                        next_fixed[i] = s * v.signum();
                        excess[i] = (v.abs() - s) / s;
                        false
                    }
                }
            })
            .collect();
        if next_active == state.active && next_fixed == state.fixed {
            let refined = (step.residual, step.refinements);
            return self.settled(data, monitor, state, step.x, refined);
        }
        if state.iter >= CHECK_MOVING_FROM && state.budget.spend() {
            if let Some(outcome) = self.check_moving(data, monitor, state, &next_active) {
                return Some(outcome);
            }
        }
        if state.seen.contains(&codes(&next_active, &next_fixed)) {
            // Before giving up, rule out round-off: the dense steps' sets come from the dense H
            // (errors of about ε/ρ of its size, ρ = A's smallest pivot ratio), the refined
            // steps' from plain sparse solves; the same set is solved again refined, then with
            // the mixed-precision solves.
            if state.dense_phase || !state.accurate {
                state.accurate = !state.dense_phase;
                state.leave_dense_phase();
                state.redo = true;
                return None;
            }
            let lambda_clipped = self.clamp(&state.lambda);
            let why = format!(
                "the active set cycles although each set's Newton step is solved to round-off (primal residual {step_residual:.1e} on its rows, refinement contracting by {contraction:.2} per correction, mixed-precision solves): the active-set rule itself does not converge on this dual (the dual Hessian of a slender body held at one point is no M-matrix: dropping a row moves the body far), not its accuracy"
            );
            return Some(finish_at_limit(
                data,
                monitor,
                state.iter,
                lambda_clipped,
                QpStatus::Inaccurate,
                why,
            ));
        }
        state.active = next_active;
        state.fixed = next_fixed;
        state.excess = excess;
        None
    }

    /// The flops of the step just taken on `state`'s set: its dense factorisation and products
    /// with H (none without H), and one check's worth for each sparse solve it made (the
    /// refined and matrix-free steps: the first evaluation and each correction; a matrix-free
    /// step makes many more, so it always pays for a check).
    fn step_flops(&self, data: &DualData<'_>, state: &State, refinements: usize) -> f64 {
        let solves = if state.dense_phase {
            0.0
        } else {
            1.0 + refinements as f64
        };
        let dense = match &self.hessian {
            Some(_) => {
                let active = state.active.iter().filter(|a| **a).count();
                CheckBudget::dense_step_flops(active, data.modes.count(), data.rows())
            }
            None => 0.0,
        };
        dense + solves * self.check_flops
    }

    /// λ projected onto each row's set: [0, ∞), or [−s, s] on a box row ([`intervals::project`],
    /// the projected methods' own).
    fn clamp(&self, lambda: &[f64]) -> Vec<f64> {
        intervals::project_all(lambda, &self.sets)
    }

    /// Whether λ lies outside some row's set.
    fn outside(&self, lambda: &[f64]) -> bool {
        self.clamp(lambda) != lambda
    }

    /// The set reproduced itself.  Settled on the dense steps: solve it again against the
    /// sparse residual.  Plain refinement is enough for a well-conditioned dual (one or two
    /// sparse solves); only when it misses the tolerance is the set solved with the
    /// mixed-precision solves (five sparse solves per evaluation).  Else the answer, with the
    /// step's x and (residual, corrections) of its refinement.
    fn settled(
        &self,
        data: &DualData<'_>,
        monitor: &mut Monitor<'_>,
        state: &mut State,
        x: Vec<f64>,
        refined: (f64, usize),
    ) -> Option<Outcome> {
        if state.dense_phase {
            state.leave_dense_phase();
            state.redo = true;
            return None;
        }
        let mut verdict = None;
        if !state.accurate {
            // Inside every row's set, λ is its own clipped value: the verdict of this check
            // is the answer's (no second check of the same (x, λ)).
            verdict = (!self.outside(&state.lambda))
                .then(|| monitor.check(data, state.iter, &state.lambda, &x));
            if !matches!(verdict, Some(Next::Stop(QpStatus::Solved, _))) {
                state.accurate = true;
                state.redo = true;
                return None;
            }
        }
        Some(self.answer(data, monitor, state, x, refined, verdict))
    }

    /// The settled set's answer: λ clipped at zero (x formed again if that changed λ), judged
    /// by the monitor — or by `verdict`, the monitor's check of this very (x, λ) when λ needed
    /// no clipping.
    fn answer(
        &self,
        data: &DualData<'_>,
        monitor: &mut Monitor<'_>,
        state: &State,
        x: Vec<f64>,
        (residual, corrections): (f64, usize),
        verdict: Option<Next>,
    ) -> Outcome {
        let iter = state.iter;
        let clipped = self.outside(&state.lambda);
        let lambda_clipped = self.clamp(&state.lambda);
        let x = if clipped {
            data.primal_at(&lambda_clipped, &data.multiplier)
        } else {
            x
        };
        let verdict = match verdict {
            Some(verdict) if !clipped => verdict,
            _ => monitor.check(data, iter, &lambda_clipped, &x),
        };
        let (status, message) = match verdict {
            Next::Stop(status, message) => (status, message),
            _ => (
                QpStatus::Inaccurate,
                monitor.explain(format!(
                    "active set settled but the KKT residuals ({:.1e}) miss the tolerance {:.1e} (refined primal residual {residual:.1e} after {corrections} corrections)",
                    monitor.last_worst(),
                    monitor.tol()
                )),
            ),
        };
        Outcome {
            x,
            multipliers: lambda_clipped,
            status,
            iterations: iter,
            message: format!("{message}; {}", self.tally(state)),
        }
    }

    /// The set can move on round-off alone while the iterate already meets the tolerance:
    /// a body 1e30 times softer than its neighbours makes νᵢ / Hᵢᵢ noise around zero, and
    /// each new set costs a dense factorisation of up to m rows.  From a few steps on, one
    /// sparse solve checks the iterate first (cheaper than that factorisation); the answer
    /// when it meets the tolerance or the moving set has stalled.
    fn check_moving(
        &self,
        data: &DualData<'_>,
        monitor: &Monitor<'_>,
        state: &mut State,
        next_active: &[bool],
    ) -> Option<Outcome> {
        let (checked, worst) =
            checked_iterate(data, monitor, state.iter, &self.clamp(&state.lambda));
        if checked.status == QpStatus::Solved {
            return Some(Outcome {
                message: format!(
                    "{}; the iterate met the tolerance while the active set still moved (on round-off); {}",
                    checked.message,
                    self.tally(state)
                ),
                ..checked
            });
        }
        let changes = (0..data.rows())
            .filter(|&i| next_active[i] != state.active[i])
            .count();
        let count = |set: &[bool]| set.iter().filter(|a| **a).count();
        let sizes = (count(&state.active), count(next_active), data.rows());
        let why = state.stall.observe(state.iter, changes, worst, sizes)?;
        Some(Outcome {
            message: format!("{}; {why}; {}", checked.message, self.tally(state)),
            ..checked
        })
    }

    /// "12 active-set steps (dense Newton steps), 3 refinement solves" for messages.
    fn tally(&self, state: &State) -> String {
        format!(
            "{} active-set steps ({}), {} refinement solves",
            state.iter, self.mode, state.refinements
        )
    }
}

/// A set with its fixed multipliers' signs as one key: 1 active, 0 inactive, ±2 slipping.
fn codes(active: &[bool], fixed: &[f64]) -> Vec<i8> {
    active
        .iter()
        .zip(fixed)
        .map(|(&on, f)| match (on, f.partial_cmp(&0.0)) {
            (true, _) => 1,
            (false, Some(std::cmp::Ordering::Greater)) => 2,
            (false, Some(std::cmp::Ordering::Less)) => -2,
            _ => 0,
        })
        .collect()
}

/// The iterate λ (already projected onto its rows' sets) as an answer, `solved` when its KKT residuals meet the
/// tolerance (else `inaccurate`), with the worst residual.
fn checked_iterate(
    data: &DualData<'_>,
    monitor: &Monitor<'_>,
    iter: usize,
    lambda: &[f64],
) -> (Outcome, f64) {
    let clipped = lambda.to_vec();
    let x = data.primal(&clipped);
    let r = monitor.residuals(&x, &clipped);
    let tol = monitor.tol();
    let (status, relation) = if r.meet(tol) {
        (QpStatus::Solved, "≤")
    } else {
        (QpStatus::Inaccurate, ">")
    };
    let outcome = Outcome {
        x,
        multipliers: clipped,
        status,
        iterations: iter,
        message: format!("KKT residuals {:.1e} {relation} tol {tol:.1e}", r.worst()),
    };
    (outcome, r.worst())
}

/// A finite answer (x = A⁺f) with a verdict and no iterations.
fn stopped(data: &DualData<'_>, status: QpStatus, message: String) -> Outcome {
    Outcome {
        x: data.base().to_vec(),
        multipliers: vec![0.0; data.rows()],
        status,
        iterations: 0,
        message,
    }
}
