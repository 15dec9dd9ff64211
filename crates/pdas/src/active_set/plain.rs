//! The plain active-set steps: each step solves the KKT system of the current set (through a
//! fresh factorisation or a low-rank update of the factored set's), refines it when the set
//! predicts itself, and then decides — accept, re-check on a fresh factor, certify, give up,
//! hand over to the interior-point iteration of [`super::interior`], or move to the next set.

use std::collections::HashSet;
use std::time::Instant;

use signorini_qp::{QpProblem, QpStatus};

use super::{
    count, settled_message, ActiveSet, Best, InteriorStart, Measured, Outcome, Phase1, Timing,
};
use crate::coupling::Coupling;
use crate::error::PdasError;
use crate::refine::{first_rhs, first_solution, first_solve, refine, SetSolution};
use crate::update::{SetSolver, SetUpdate};

/// Plain active-set steps before a step that does not reduce the changes hands over to the
/// interior-point iteration (a set that comes back hands over at once).  Measured: handing
/// over from the third step on turned exp6a, exp6b, exp3-body2-h0.15, hard/near-coincident
/// and hard/slave-on-master-nodes from 5 plain steps into 12–16; from the sixth, no fixture
/// hands over, and strip-partial hands over after its seventh.
const MIN_PLAIN_STEPS: usize = 6;

/// The plain iteration's state, carried from one step to the next.
pub(super) struct Plain {
    /// The current set F_k.
    active: Vec<bool>,
    /// Per row, the sign of a slipping box row's fixed multiplier ±s (0 on other rows).
    signs: Vec<f64>,
    /// The sets stepped from so far, with their signs (one that comes back is a cycle).
    seen: HashSet<Vec<i8>>,
    /// The best iterate so far.
    pub(super) best: Best,
    /// The set whose numeric factor is held, once there is one.
    factored: Option<Vec<bool>>,
    /// Measured cost of the last factorisation and of solves with it.
    timing: Timing,
    /// Factorise the current set even where an update would do (an update's answer is in doubt).
    force_factor: bool,
    /// Per step so far: the rows that changed and the worst scaled KKT residual.
    history: Vec<Progress>,
    /// The current step (1-based once running).
    pub(super) iteration: usize,
    /// The iteration cap.
    max_iter: usize,
    /// Iterations before this run of plain steps (0, or those up to a crossover).
    before: usize,
    /// The primal regularisation ρ of its factorisations.
    rho: f64,
    /// Appended to the message of a set that reproduces itself ("" in the first phase).
    note: String,
}

impl Plain {
    /// The state before the first step: set `active` with `signs`, a zero iterate as the best
    /// so far.
    fn new(
        problem: &QpProblem,
        (active, signs): (Vec<bool>, Vec<f64>),
        max_iter: usize,
        rho: f64,
    ) -> Self {
        Self {
            signs,
            active,
            seen: HashSet::new(),
            best: Best::zero(problem),
            factored: None,
            timing: Timing::default(),
            force_factor: false,
            history: Vec::new(),
            iteration: 0,
            max_iter,
            before: 0,
            rho,
            note: String::new(),
        }
    }

    /// The state of a crossover from the interior-point iteration: steps from `set` (one-sided
    /// rows only) after `iteration` iterations with the best iterate `best`, factorised with
    /// ρ = 0 (see the crate's docs), `note` appended to the messages of a settled set.
    pub(super) fn crossover(
        set: Vec<bool>,
        (iteration, max_iter): (usize, usize),
        best: Best,
        note: String,
    ) -> Self {
        let rows = set.len();
        Self {
            signs: vec![0.0; rows],
            active: set,
            seen: HashSet::new(),
            best,
            factored: None,
            timing: Timing::default(),
            force_factor: false,
            history: Vec::new(),
            iteration,
            max_iter,
            before: iteration,
            rho: 0.0,
            note,
        }
    }
}

/// What a step leads to.
pub(super) enum Flow {
    /// The next step (on the next set, or on this one again with a fresh factor).
    Next,
    /// The iteration is over.
    Done(Outcome),
    /// The sets flip: the interior-point iteration takes over from (x, λ).
    Handover {
        /// x of the last step.
        x: Vec<f64>,
        /// λ of the last step (not clamped).
        multipliers: Vec<f64>,
    },
}

/// How the KKT system of the current set is solved this step.
struct SetSolve {
    /// The update from the factored set, or none when the factor is the set's own.
    update: Option<SetUpdate>,
    /// Whether the set was factorised this step.
    fresh: bool,
    /// The set's first solve, K_F⁻¹ [`first_rhs`], when it was solved in the update's batch.
    first: Option<Vec<f64>>,
    /// Coulomb's coupling of the set's slipping rows (none without them), built once per step.
    coupling: Option<Coupling>,
}

impl ActiveSet<'_> {
    /// Runs the iteration.
    pub fn run(&mut self) -> Outcome {
        let max_iter = self.options.max_iter.unwrap_or(self.settings.max_iter);
        if self.starts_interior() {
            let phase1 = Phase1 {
                iteration: 0,
                best: Best::zero(self.problem),
            };
            return self.interior(InteriorStart::Centred, phase1, max_iter);
        }
        let mut state = Plain::new(self.problem, self.first_set(), max_iter, self.rho());
        match self.steps(&mut state) {
            Some(Flow::Done(outcome)) => return outcome,
            Some(Flow::Handover { x, multipliers }) => {
                let phase1 = Phase1 {
                    iteration: state.iteration,
                    best: state.best,
                };
                let start = InteriorStart::HandedOver {
                    x,
                    multipliers: &multipliers,
                };
                return self.interior(start, phase1, max_iter);
            }
            Some(Flow::Next) | None => {}
        }
        let message = format!(
            "{max_iter} active-set iterations without meeting the tolerance (best KKT residuals {:.1e})",
            state.best.worst
        );
        self.finish(
            state.best.outcome,
            QpStatus::MaxIterations,
            max_iter,
            message,
        )
    }

    /// Plain steps from `state` until one ends the solve or hands over (never
    /// [`Flow::Next`]); `None` at the iteration cap.
    pub(super) fn steps(&mut self, state: &mut Plain) -> Option<Flow> {
        while state.iteration < state.max_iter {
            state.iteration += 1;
            match self.plain_step(state) {
                Flow::Next => {}
                end => return Some(end),
            }
        }
        None
    }

    /// One plain step: solve the current set, then decide.
    fn plain_step(&mut self, state: &mut Plain) -> Flow {
        let iteration = state.iteration;
        if self.out_of_time() {
            return Flow::Done(self.finish(
                state.best.take(),
                QpStatus::TimeLimit,
                iteration - 1,
                "time limit reached before the next factorisation".into(),
            ));
        }
        let mut set_solve = match self.prepare_solve(state) {
            Ok(s) => s,
            Err(e) => {
                return Flow::Done(self.finish(
                    state.best.take(),
                    QpStatus::NumericalError,
                    iteration - 1,
                    e.to_string(),
                ))
            }
        };
        let (solution, next, signs) = self.solve_set(state, &mut set_solve);
        if !solution.is_finite() {
            if set_solve.update.is_some() {
                state.force_factor = true;
                return Flow::Next;
            }
            return Flow::Done(self.finish(
                state.best.take(),
                QpStatus::NumericalError,
                iteration,
                format!(
                    "non-finite solution of the KKT system on a set of {} rows",
                    count(&state.active)
                ),
            ));
        }
        self.decide(state, solution, (next, signs), &set_solve)
    }

    /// Makes the current set solvable: a low-rank update of the factored set's factor when
    /// [`ActiveSet::prefer_update`] says so (and the update is not singular), else a
    /// factorisation unless the factor already is the set's.
    fn prepare_solve(&mut self, state: &mut Plain) -> Result<SetSolve, PdasError> {
        let p = self.problem;
        let delta = self.delta();
        let mut first = None;
        let coupling = self.coupling(&state.active, &state.signs);
        let update = match &state.factored {
            Some(f)
                if !state.force_factor
                    && self.prefer_update(f, &state.active, &state.timing, coupling.is_none()) =>
            {
                let (_, missing) = self.cache.need(f, &state.active);
                // The set's first solve joins the batch of the missing columns (one pass over
                // the factor for both), except with Coulomb's coupling, whose solves iterate.
                first = coupling
                    .is_none()
                    .then(|| first_rhs(p, &state.active, self.fixed_of(state).as_deref()));
                let clock = Instant::now();
                let update = SetUpdate::new(
                    p,
                    &mut self.factor,
                    &mut self.cache,
                    (f, &state.active),
                    delta,
                    first.as_deref_mut(),
                );
                if missing > 0 {
                    let columns = missing + usize::from(first.is_some());
                    state.timing.column = clock.elapsed() / columns as u32;
                }
                update?
            }
            _ => None,
        };
        if update.is_none() {
            // Solved (if at all) for an update that did not come about.
            first = None;
        }
        let fresh = update.is_none() && state.factored.as_ref() != Some(&state.active);
        state.force_factor = false;
        if fresh {
            state.timing.factor = self.factorise_with(&state.active, delta, state.rho)?;
            self.cache.clear();
            state.factored = Some(state.active.clone());
        }
        if update.is_some() {
            self.updates += 1;
        }
        Ok(SetSolve {
            update,
            fresh,
            first,
            coupling,
        })
    }

    /// The fixed multipliers of the current set's inactive rows, when the problem has box rows.
    fn fixed_of(&self, state: &Plain) -> Option<Vec<f64>> {
        self.has_box()
            .then(|| self.fixed(&state.active, &state.signs))
    }

    /// Solves the current set (timing the solve of a fresh factor), refines the solution when
    /// the set predicts itself or a set seen before, and returns it with the set it predicts.
    fn solve_set(
        &mut self,
        state: &mut Plain,
        set_solve: &mut SetSolve,
    ) -> (SetSolution, Vec<bool>, Vec<f64>) {
        let p = self.problem;
        let limits = self.limits();
        let fixed = self.fixed_of(state);
        let mut solver = SetSolver {
            factor: &mut self.factor,
            update: set_solve.update.as_ref(),
            coupling: set_solve.coupling.as_ref(),
        };
        let clock = Instant::now();
        let mut solution = match set_solve.first.take() {
            Some(z) => first_solution(p, &state.active, fixed.as_deref(), &solver, z),
            None => first_solve(p, &state.active, fixed.as_deref(), &mut solver),
        };
        if set_solve.fresh {
            state.timing.solve = clock.elapsed();
            if state.timing.column.is_zero() {
                // Until a batch is measured: a column of a batched solve at half a solve.
                state.timing.column = state.timing.solve / 2;
            }
        }
        let (mut next, mut signs) = self.next_state(&solution);
        // A set that predicts itself is judged on a refined solution, and so is one that
        // predicts a set seen before: a row at the edge of the contact zone whose multiplier
        // and gap are both at round-off can flip on an unrefined solution, and a cycle is
        // only judged on a factorised set (`decide`), which costs a factorisation where a
        // refinement step or two settle it.
        let settles = next == state.active && signs == state.signs;
        if settles || state.seen.contains(&codes(&next, &signs)) {
            let mut solver = SetSolver {
                factor: &mut self.factor,
                update: set_solve.update.as_ref(),
                coupling: set_solve.coupling.as_ref(),
            };
            refine(
                p,
                &self.scales,
                &state.active,
                &mut solver,
                &mut solution,
                &limits,
            );
            self.refinement_steps += solution.steps;
            (next, signs) = self.next_state(&solution);
        }
        (solution, next, signs)
    }

    /// Judges the step's solution: accepts it, asks for the set again on a fresh factor,
    /// certifies infeasibility, or (in [`ActiveSet::move_on`]) keeps it as the best and moves on.
    fn decide(
        &mut self,
        state: &mut Plain,
        mut solution: SetSolution,
        (next, signs): (Vec<bool>, Vec<f64>),
        set_solve: &SetSolve,
    ) -> Flow {
        let iteration = state.iteration;
        let x = std::mem::take(&mut solution.x);
        let mut measured = self.measure(x, &solution.multipliers, &state.active, &next, iteration);
        // A slipping box row that turns round changes the set too.
        measured.changes += next
            .iter()
            .zip(&state.active)
            .zip(signs.iter().zip(&state.signs))
            .filter(|((a, b), (s, t))| a == b && !**a && s != t)
            .count();
        let key = codes(&next, &signs);
        if self.options.verbose {
            log_step(iteration, &state.active, set_solve, &solution, &measured);
        }
        let Measured {
            candidate,
            residuals,
            worst,
            changes,
        } = measured;
        let stalled = changes == 0;
        // An answer is accepted on a set that reproduces itself (or at the end of a cycle or
        // of the budget): residuals that meet the tolerance while rows still want to change
        // can hide a penetration that a soft row's length scale makes look small.
        let settled = stalled || state.seen.contains(&key) || iteration == state.max_iter;
        if residuals.meet(self.options.tol) && settled {
            let message = format!("{} active rows{}", count(&state.active), state.note);
            return Flow::Done(self.finish(candidate, QpStatus::Solved, iteration, message));
        }
        if stalled && set_solve.update.is_some() {
            // The update may have lost accuracy: factorise this set before judging it.
            state.force_factor = true;
            return Flow::Next;
        }
        let cycling = !stalled && state.seen.contains(&key);
        if cycling && set_solve.update.is_some() {
            // As for a settled set: judge a cycle only on a factorised set.
            state.force_factor = true;
            return Flow::Next;
        }
        if stalled || cycling || solution.timed_out || iteration == state.max_iter {
            if let Some((status, message)) =
                self.certificate(&candidate.x, &solution.multipliers, &solution.correction)
            {
                return Flow::Done(self.finish(candidate, status, iteration, message));
            }
        }
        let step = Judged {
            candidate,
            worst,
            changes,
            cycling,
        };
        self.move_on(state, solution, (next, signs), step)
    }

    /// After a step that is neither accepted nor certified: keeps the best iterate, stops on
    /// the time limit or a settled set that misses the tolerance, hands over to the
    /// interior-point iteration when the sets flip, or moves to the next set.
    fn move_on(
        &mut self,
        state: &mut Plain,
        solution: SetSolution,
        (next, signs): (Vec<bool>, Vec<f64>),
        step: Judged,
    ) -> Flow {
        let p = self.problem;
        let iteration = state.iteration;
        let stalled = step.changes == 0;
        let progress = step.progress();
        // Counted from this run's first step: a crossover's plain steps get their chance too.
        let flipping = flipping(&state.history, progress, iteration - state.before);
        // Box rows have no interior-point continuation: their plain steps go on while the sets
        // still change without repeating (a contact zone that shrinks a node per side each step
        // changes as many rows as two steps before without flipping).
        // A step that changes more rows than a low-rank update takes
        // ([`crate::PdasSettings::max_update_rank`]) hands over at once, from the first step on
        // (issue 21): the next set would cost a factorisation, and on a long interface such
        // changes are where the plain steps flip.  Measured on strip-partial (51 575 DOFs, 2001
        // rows, the first step drops 689): 13 factorisations (7 plain steps) before, 5 after; no
        // seed or hard fixture changes that many rows in a step (m ≤ 301).
        let wholesale = step.changes > self.settings.max_update_rank;
        let flipping = (flipping || wholesale) && !self.has_box();
        let restart = ((step.cycling || flipping) && iteration < state.max_iter)
            .then(|| (step.candidate.x.clone(), solution.multipliers.clone()));
        state.best.keep_if_better(step.candidate, step.worst);
        if solution.timed_out {
            return Flow::Done(self.finish(
                state.best.take(),
                QpStatus::TimeLimit,
                iteration,
                "time limit reached during refinement".into(),
            ));
        }
        if stalled {
            let message = settled_message(
                p,
                count(&state.active),
                (step.worst, solution.residual),
                &solution.multipliers,
            ) + &state.note;
            return Flow::Done(self.finish(
                state.best.take(),
                QpStatus::Inaccurate,
                iteration,
                message,
            ));
        }
        if restart.is_some() && self.has_box() {
            let message = format!(
                "the active sets cycle (best KKT residuals {:.1e}); the interior-point continuation knows one-sided rows only, not friction's box rows",
                state.best.worst
            );
            return Flow::Done(self.finish(
                state.best.take(),
                QpStatus::Inaccurate,
                iteration,
                message,
            ));
        }
        if let Some((x, multipliers)) = restart {
            // A set came back, or the changes stopped falling: plain active-set steps are
            // not converging here; continue with the globalised iteration from this point.
            return Flow::Handover { x, multipliers };
        }
        state.history.push(progress);
        state.seen.insert(codes(&state.active, &state.signs));
        state.active = next;
        state.signs = signs;
        Flow::Next
    }
}

/// One plain step's progress: the rows that change for the next set and the worst scaled KKT
/// residual of its answer.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Progress {
    changes: usize,
    worst: f64,
}

/// Whether the plain steps flip, judged at step `iteration` (1-based) with `step`'s progress
/// after the steps of `history`: as many rows change as two steps before (or more), and
/// either the plain steps have had their chance ([`MIN_PLAIN_STEPS`]: the seed and hard
/// fixtures settle within 4–7 steps, some with a step that changes as many rows as the one
/// two before) or the KKT residual has not fallen over those two steps either — no measure of
/// progress moves, from the third step on.  Measured with `--verbose` over the 53 fixtures:
/// only `hard/strip-thin-partial` shows neither falling (changes 238, 224, 254; residuals
/// 1.5e-2, 2.2e-2, 2.0e-2), and it flipped on to its sixth step; Hertz's peeling contact zone
/// changes as many rows as two steps before (22, 63, 22) while its residual falls (2.0e2,
/// 7.4e1, 9.0e1) and settles in 14 plain steps.
fn flipping(history: &[Progress], step: Progress, iteration: usize) -> bool {
    let Some(before) = history.len().checked_sub(2).map(|k| history[k]) else {
        return false;
    };
    let more_changes = step.changes >= before.changes;
    let no_progress = more_changes && step.worst >= before.worst;
    more_changes && (iteration >= MIN_PLAIN_STEPS || no_progress)
}

/// A set with its signs as one key: 1 active, 0 inactive, ±2 slipping box rows.
fn codes(active: &[bool], signs: &[f64]) -> Vec<i8> {
    active
        .iter()
        .zip(signs)
        .map(|(&on, s)| {
            if on {
                1
            } else if *s > 0.0 {
                2
            } else if *s < 0.0 {
                -2
            } else {
                0
            }
        })
        .collect()
}

/// A step's solution, measured and neither accepted nor certified.
struct Judged {
    /// (x, max(λ, 0)) as an answer.
    candidate: Outcome,
    /// Its worst scaled KKT residual.
    worst: f64,
    /// Rows that change for the next set.
    changes: usize,
    /// Whether the next set was stepped from before.
    cycling: bool,
}

impl Judged {
    /// The step's progress measures.
    fn progress(&self) -> Progress {
        Progress {
            changes: self.changes,
            worst: self.worst,
        }
    }
}

/// The verbose line of one plain step.
fn log_step(
    iteration: usize,
    active: &[bool],
    set_solve: &SetSolve,
    solution: &SetSolution,
    measured: &Measured,
) {
    eprintln!(
        "pdas: iteration {iteration}: {} active rows ({}), KKT system residual {:.1e} after {} refinement steps, KKT {:.1e}, {} changes",
        count(active),
        match (&set_solve.update, set_solve.fresh) {
            (Some(u), _) => format!("update of rank {}", u.rank()),
            (None, true) => "factorised".to_string(),
            (None, false) => "same factor".to_string(),
        },
        solution.residual,
        solution.steps,
        measured.worst,
        measured.changes,
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The steps' (changes, worst KKT residual) as `--verbose` printed them before the rule.
    fn steps(measured: &[(usize, f64)]) -> Vec<Progress> {
        measured
            .iter()
            .map(|&(changes, worst)| Progress { changes, worst })
            .collect()
    }

    /// The first step (1-based) at which [`flipping`] hands over, if any.
    fn hands_over_at(measured: &[(usize, f64)]) -> Option<usize> {
        let steps = steps(measured);
        (0..steps.len()).find_map(|k| flipping(&steps[..k], steps[k], k + 1).then_some(k + 1))
    }

    #[test]
    fn steps_that_make_no_progress_by_either_measure_hand_over_at_the_third() {
        // hard/strip-thin-partial (pdas, --verbose): the plain steps flipped to the sixth.
        let partial = [
            (238, 1.5e-2),
            (224, 2.2e-2),
            (254, 2.0e-2),
            (212, 1.8e-2),
            (213, 1.7e-2),
            (234, 1.5e-2),
        ];
        assert_eq!(hands_over_at(&partial), Some(3));
    }

    #[test]
    fn a_peeling_zone_whose_residual_falls_keeps_its_plain_steps() {
        // accuracy/hertz.toml: the zone shrinks by ~20 rows a step, as many as two steps
        // before, but the residual falls; the plain steps settle at the 14th.
        let hertz = [
            (22, 2.0e2),
            (63, 7.4e1),
            (22, 9.0e1),
            (40, 5.3e1),
            (22, 2.7e1),
            (20, 2.2e1),
            (11, 1.1e1),
            (11, 8.7e0),
            (9, 4.9e0),
            (6, 3.2e0),
            (3, 1.6e0),
            (2, 1.1e0),
            (2, 6.5e-1),
        ];
        assert_eq!(hands_over_at(&hertz), None);
        // Without falling residuals the same changes are flipping (from the sixth step on,
        // as before the rule, the changes alone).
        let stuck: Vec<(usize, f64)> = hertz.iter().map(|&(c, _)| (c, 1.0)).collect();
        assert_eq!(hands_over_at(&stuck), Some(3));
    }
}
