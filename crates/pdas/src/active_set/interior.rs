//! The globalised iteration, taken over from the plain one when its sets flip (or started
//! from a centred point on a curved interface, [`crate::StartSet::Auto`]): a primal–dual
//! interior-point method (Mehrotra's predictor–corrector) on the same fixed-pattern KKT
//! matrix, with a crossover to the exact active-set solve.
//!
//! ```text
//! minimise ½ xᵀA x − fᵀx   subject to   B x + s = g,  s ≥ 0,  λ ≥ 0,  s ∘ λ → 0
//! [ A    Bᵀ ] [Δx]   [ −r_d                          ]     r_d = A x + Bᵀλ − f
//! [ B   −D  ] [Δλ] = [ −r_p + s + (Δs_a ∘ Δλ_a − σμ)/λ ],  r_p = B x + s − g,  D = diag(s/λ)
//! ```
//!
//! Every row is in the pattern with its B entries (the pattern of the active-set iteration
//! with every row active), so each interior step is one numeric LDLᵀ of the one symbolic
//! factor, quasi-definite as before (D > 0).  Unlike an active-set step, an interior step moves
//! every row's status a little at a time, so a change that is non-local (a thin strip lifting
//! one end when a row far away is released) does not flip sets back and forth: the iteration
//! count does not depend on how many rows change, and the complementarity μ falls by a
//! factor each step.  The set the iterate predicts, { i : λᵢ Xᵢ > sᵢ F } (forces and gaps in
//! the units of the KKT residuals), is solved exactly after the first interior step, and later
//! whenever it is the same twice in a row with μ fallen tenfold: the crossover is a run of
//! plain active-set steps from that set — its KKT system factorised with ρ = 0 (the crate's docs
//! say why) and refined, then low-rank updates of that factor while few rows
//! change — accepted only on a set that reproduces itself and meets the tolerance, and handed
//! back to the interior steps when the plain steps flip.  The interior iterate only has to
//! find the set, never to be accurate itself.
//!
//! Crossing over after the first step (issue 21): on the long partial-contact strips the
//! first step's set is right or a few rows off (m = 2 001: the 403 rows of the answer; m =
//! 20 001: 4 005 rows, 2 from the answer's 4 003), which the updates fix, so the solve takes
//! three factorisations (the plain step, one interior step, the crossover) instead of four
//! and six.  A first set that is far off costs one factorisation: the plain step that finds
//! more changes than an update takes hands back at once.  That first step is the predictor
//! alone (no corrector solve): on every fixture it predicts the same set as the full step
//! (strip-thin-partial 403 rows, the clamped strip 410, `partial1000` 4 005, hertz-graded 52).

use std::time::Instant;

use signorini_qp::{
    dot, kkt_residuals_with, mat_t_vec, mat_vec, QpProblem, QpStatus, ResidualScales,
};

use super::plain::{Flow, Plain};
use super::{count, ActiveSet, Best, InteriorStart, Outcome, Phase1};

/// Fraction of the distance to the boundary an interior step may go.
const TO_BOUNDARY: f64 = 0.995;

/// The start's shift into the interior, in the units of the KKT residuals: sᵢ = (g − B x)ᵢ⁺ +
/// `START_SHIFT` Xᵢ and λᵢ = λᵢ⁺ + `START_SHIFT` F (issue 21).  Factorisations to solved on
/// strip-partial floating / clamped at its left end, handed over after the first plain step:
/// 0.01 → 6 / –, 0.1 → 5 / 9, 1 → 7 / –; Mehrotra's start (its centring shift ×10³, the
/// earlier rule) → 82 / max-iterations (from the first step's iterate, every gap ≈ 0, its
/// centring shift is ≈ 0 and the iterate starts at the boundary), and 13 / 21 when handed
/// over after the seventh plain step as before.
const START_SHIFT: f64 = 0.1;

/// λᵢ of the centred start ([`InteriorStart::Centred`]) in units of the force scale F (sᵢ =
/// gᵢ⁺ + [`START_SHIFT`] Xᵢ as after a hand-over).  Factorisations + low-rank updates to solved
/// with λᵢ = 0.1 F / F / 10 F (`solve SCENE --backend pdas --tol 1e-8`, the start forced):
/// accuracy/hertz 4 + 7 / **3 + 5** / 4 + 7, accuracy/hertz-graded 4 + 4 / **3 + 3** / 3 + 4,
/// the partial strips (flush, where [`crate::StartSet::Auto`] does not start here) hard/
/// strip-thin-partial 2 + 1 / 2 + 1 / 2 + 0, the clamped one 2 + 5 / 2 + 6 / 7 + 4 and the
/// one of 20 001 rows 8 + 1 / 2 + 1 / 2 + 1.
const CENTRED_MULTIPLIER: f64 = 1.0;

/// The interior-point iteration's state, carried from one step to the next.
struct Interior {
    /// Primal x.
    x: Vec<f64>,
    /// Slacks s = g − B x (at the solution), kept positive.
    s: Vec<f64>,
    /// Multipliers λ, kept positive.
    lambda: Vec<f64>,
    /// Iterations so far (the plain steps' included).
    iteration: usize,
    /// The iteration cap.
    max_iter: usize,
    /// The best iterate so far.
    best: Best,
    /// The set the last step predicted.
    previous: Option<Vec<bool>>,
    /// Sets solved exactly so far.
    tried: Vec<Vec<bool>>,
    /// Interior-point steps taken.
    steps: usize,
    /// μ at the first interior step.
    first_mu: Option<f64>,
    /// Whether the plain steps handed over (else the iteration started here).
    handed_over: bool,
}

impl Interior {
    /// Records the set a step at complementarity `mu` predicts; whether to cross over to it:
    /// the first step's set (not tried yet), and after it a set that repeats the last step's,
    /// was not tried yet, and with μ fallen tenfold from the first step's.
    fn crossover_due(&mut self, set: &[bool], mu: f64) -> bool {
        let repeated = self.previous.as_deref() == Some(set);
        self.previous = Some(set.to_vec());
        let Some(mu0) = self.first_mu else {
            // The first step's set, at once (the module's docs say why).
            self.first_mu = Some(mu);
            return !self.tried.iter().any(|t| t == set);
        };
        // (Written as the negation of the reasons against, so that a NaN μ behaves as before.)
        let against = !repeated || self.tried.iter().any(|t| t == set) || mu > 0.1 * mu0;
        !against
    }
}

/// The Newton direction of one interior step.
struct Direction {
    /// Δx.
    dx: Vec<f64>,
    /// Δλ.
    dl: Vec<f64>,
    /// Δs = −r_p − B Δx.
    ds: Vec<f64>,
}

/// What an interior step measured, for the verbose log.
struct Stepped {
    /// Complementarity μ = sᵀλ / m before the step.
    mu: f64,
    /// Centring σ.
    sigma: f64,
    /// Step length α.
    alpha: f64,
}

impl ActiveSet<'_> {
    /// Runs the interior-point iteration from `start` until the iteration cap, the time limit
    /// or an accepted crossover.
    pub(super) fn interior(
        &mut self,
        start: InteriorStart<'_>,
        phase1: Phase1,
        max_iter: usize,
    ) -> Outcome {
        let p = self.problem;
        let handed_over = matches!(start, InteriorStart::HandedOver { .. });
        let (x, s, lambda) = match start {
            InteriorStart::HandedOver { x, multipliers } => {
                let (s, lambda) = shifted_start(p, &self.scales, &x, multipliers, START_SHIFT);
                (x, s, lambda)
            }
            InteriorStart::Centred => {
                let (x, zero) = (vec![0.0; p.dofs()], vec![0.0; p.rows()]);
                let (s, lambda) = shifted_start(p, &self.scales, &x, &zero, CENTRED_MULTIPLIER);
                (x, s, lambda)
            }
        };
        let mut state = Interior {
            x,
            s,
            lambda,
            iteration: phase1.iteration,
            max_iter,
            best: phase1.best,
            previous: None,
            tried: Vec::new(),
            steps: 0,
            first_mu: None,
            handed_over,
        };
        loop {
            if state.iteration >= max_iter || self.out_of_time() {
                return self.interior_limit(state);
            }
            state.iteration += 1;
            state.steps += 1;
            let stepped = match self.interior_step(&mut state) {
                Ok(stepped) => stepped,
                Err(outcome) => return outcome,
            };
            let set = self.predicted_set(&state);
            if self.options.verbose {
                eprintln!(
                    "pdas: iteration {}: interior step, μ {:.2e}, σ {:.2e}, α {:.3}, {} rows predicted active",
                    state.iteration,
                    stepped.mu,
                    stepped.sigma,
                    stepped.alpha,
                    count(&set)
                );
            }
            if !state.crossover_due(&set, stepped.mu) {
                continue;
            }
            if let Some(outcome) = self.crossover(&mut state, set) {
                return outcome;
            }
        }
    }

    /// Keeps the interior iterate (x, λ⁺) as the best answer when its KKT residuals are the
    /// smallest so far: the answer of an iteration that stops before an exact solve is accepted
    /// (started here, nothing else has been measured).  Only at such a stop: the steps
    /// themselves never need it.
    fn keep_iterate(&self, state: &mut Interior) {
        let multipliers = self.clamp(&state.lambda);
        let worst = kkt_residuals_with(self.problem, &self.scales, &state.x, &multipliers).worst();
        let candidate = Outcome {
            x: state.x.clone(),
            multipliers,
            status: QpStatus::Solved,
            iterations: state.iteration,
            message: String::new(),
        };
        state.best.keep_if_better(candidate, worst);
    }

    /// The end at the iteration cap or the time limit.
    fn interior_limit(&self, mut state: Interior) -> Outcome {
        self.keep_iterate(&mut state);
        let (status, why) = if state.iteration >= state.max_iter {
            (
                QpStatus::MaxIterations,
                format!("{} iterations", state.max_iter),
            )
        } else {
            (QpStatus::TimeLimit, "time limit reached".to_string())
        };
        let phase = if state.handed_over {
            "after the active-set steps flipped"
        } else {
            "from the centred start"
        };
        let message = format!(
            "{why} without meeting the tolerance (interior-point iteration {phase}: {} interior steps; best KKT residuals {:.1e})",
            state.steps, state.best.worst
        );
        self.finish(state.best.outcome, status, state.iteration, message)
    }

    /// One predictor–corrector step: factorises K with D = diag(s/λ) and moves (x, s, λ);
    /// `Err` with the final answer when the factorisation or the step fails.
    fn interior_step(&mut self, state: &mut Interior) -> Result<Stepped, Outcome> {
        let p = self.problem;
        let m = p.rows();
        let (r_d, r_p) = interior_residuals(p, state);
        let (s, lambda) = (&state.s, &state.lambda);
        let mu = dot(s, lambda) / m.max(1) as f64;
        let floor = 1e-3 * self.delta();
        let diagonal: Vec<f64> = (0..m).map(|i| (s[i] / lambda[i]).max(floor)).collect();
        let clock = Instant::now();
        self.kkt.set_diagonal(0.0, &diagonal);
        if let Err(e) = self.factor_values(clock) {
            self.keep_iterate(state);
            let iteration = state.iteration;
            return Err(self.finish(
                state.best.take(),
                QpStatus::NumericalError,
                iteration,
                e.to_string(),
            ));
        }
        self.cache.clear();
        // Predictor (affine scaling).
        let tail: Vec<f64> = (0..m).map(|i| -r_p[i] + s[i]).collect();
        let affine = self.direction(&r_d, &r_p, &tail);
        // The first step only has to find the set the crossover tries next: the predictor
        // alone, without the corrector's solve.
        let (sigma, d) = if state.first_mu.is_none() {
            (0.0, affine)
        } else {
            self.corrector(state, (&r_d, &r_p), &affine, mu)
        };
        let alpha = (TO_BOUNDARY * max_step(s, &d.ds).min(max_step(lambda, &d.dl))).min(1.0);
        if alpha.is_nan() || alpha <= 0.0 || d.dx.iter().chain(&d.dl).any(|v| !v.is_finite()) {
            self.keep_iterate(state);
            let message = format!(
                "the interior-point step failed (step length {alpha:.1e}) after {} interior steps; best KKT residuals {:.1e}",
                state.steps, state.best.worst
            );
            let iteration = state.iteration;
            return Err(self.finish(state.best.take(), QpStatus::Inaccurate, iteration, message));
        }
        let step = |v: &mut Vec<f64>, dv: &[f64]| {
            v.iter_mut().zip(dv).for_each(|(v, d)| *v += alpha * d);
        };
        step(&mut state.x, &d.dx);
        step(&mut state.s, &d.ds);
        step(&mut state.lambda, &d.dl);
        Ok(Stepped { mu, sigma, alpha })
    }

    /// Mehrotra's corrector after the predictor `affine` at complementarity `mu`: the centring
    /// σ = (μ_a / μ)³, μ_a the complementarity after the predictor's longest step, and the
    /// corrected direction (one more solve with the current factor).
    fn corrector(
        &mut self,
        state: &Interior,
        (r_d, r_p): (&[f64], &[f64]),
        affine: &Direction,
        mu: f64,
    ) -> (f64, Direction) {
        let (s, lambda) = (&state.s, &state.lambda);
        let m = s.len();
        let (ds_a, dl_a) = (&affine.ds, &affine.dl);
        let alpha_a = max_step(s, ds_a).min(max_step(lambda, dl_a)).min(1.0);
        let mu_a = (0..m)
            .map(|i| (s[i] + alpha_a * ds_a[i]) * (lambda[i] + alpha_a * dl_a[i]))
            .sum::<f64>()
            / m.max(1) as f64;
        let sigma = (mu_a / mu).clamp(0.0, 1.0).powi(3);
        let tail: Vec<f64> = (0..m)
            .map(|i| -r_p[i] + s[i] + (ds_a[i] * dl_a[i] - sigma * mu) / lambda[i])
            .collect();
        (sigma, self.direction(r_d, r_p, &tail))
    }

    /// The direction for the right-hand side [−r_d; `tail`] with the current factor.
    fn direction(&mut self, r_d: &[f64], r_p: &[f64], tail: &[f64]) -> Direction {
        let p = self.problem;
        let (n, m) = (p.dofs(), p.rows());
        let mut z: Vec<f64> = r_d.iter().map(|v| -v).chain(tail.iter().copied()).collect();
        self.factor.solve_in_place(&mut z);
        let dl = z.split_off(n);
        let bdx = mat_vec(&p.constraints, &z);
        let ds: Vec<f64> = (0..m).map(|i| -r_p[i] - bdx[i]).collect();
        Direction { dx: z, dl, ds }
    }

    /// The set the iterate predicts, { i : λᵢ Xᵢ > sᵢ F } (forces and gaps in the units of
    /// the KKT residuals).
    fn predicted_set(&self, state: &Interior) -> Vec<bool> {
        let (rows, force) = (&self.scales.rows, self.scales.force);
        (0..self.problem.rows())
            .map(|i| state.lambda[i] * rows[i] > state.s[i] * force)
            .collect()
    }

    /// Crossover: plain active-set steps from the predicted set on — its exact solve (a
    /// factorisation with ρ = 0, refined), then low-rank updates of that factor while few rows
    /// change — for as long as the plain steps would go on.  The final answer when one is
    /// accepted, settles, is certified, or the time runs out (`plain_step`'s own checks);
    /// `None` to go on with interior steps (the plain steps flipped, or the cap was reached).
    fn crossover(&mut self, state: &mut Interior, set: Vec<bool>) -> Option<Outcome> {
        state.tried.push(set.clone());
        let why = if state.handed_over {
            "the active-set steps flipped"
        } else {
            "started from the interior-point predictor"
        };
        let note = format!(
            " ({why}; {} interior-point steps, then exact solves from the set they found)",
            state.steps
        );
        let best = std::mem::replace(&mut state.best, Best::zero(self.problem));
        let mut plain = Plain::crossover(set, (state.iteration, state.max_iter), best, note);
        let end = match self.steps(&mut plain) {
            Some(Flow::Done(outcome)) => Some(outcome),
            Some(Flow::Handover { .. } | Flow::Next) | None => None,
        };
        state.iteration = plain.iteration;
        state.best = plain.best;
        end
    }
}

/// The start (s, λ) from (x, λ): s = (g − B x)⁺ shifted into the interior by [`START_SHIFT`]
/// times each row's length scale Xᵢ, λ⁺ by `multiplier_shift` times the force scale F.
fn shifted_start(
    p: &QpProblem,
    scales: &ResidualScales,
    x: &[f64],
    multipliers: &[f64],
    multiplier_shift: f64,
) -> (Vec<f64>, Vec<f64>) {
    let bx = mat_vec(&p.constraints, x);
    let s = p
        .gap
        .iter()
        .zip(&bx)
        .zip(&scales.rows)
        .map(|((g, b), row)| (g - b).max(0.0) + START_SHIFT * row)
        .collect();
    let lambda = multipliers
        .iter()
        .map(|l| l.max(0.0) + multiplier_shift * scales.force)
        .collect();
    (s, lambda)
}

/// r_d = A x + Bᵀλ − f and r_p = B x + s − g at the state's iterate.
fn interior_residuals(p: &QpProblem, state: &Interior) -> (Vec<f64>, Vec<f64>) {
    let (n, m) = (p.dofs(), p.rows());
    let mut r_d = mat_vec(&p.stiffness, &state.x);
    let btl = mat_t_vec(&p.constraints, &state.lambda);
    for j in 0..n {
        r_d[j] += btl[j] - p.load[j];
    }
    let bx = mat_vec(&p.constraints, &state.x);
    let r_p: Vec<f64> = (0..m).map(|i| bx[i] + state.s[i] - p.gap[i]).collect();
    (r_d, r_p)
}

/// The largest α ≤ ∞ with v + α dv ≥ 0 (v > 0).
fn max_step(v: &[f64], dv: &[f64]) -> f64 {
    v.iter()
        .zip(dv)
        .filter(|(_, d)| **d < 0.0)
        .map(|(a, d)| -a / d)
        .fold(f64::INFINITY, f64::min)
}
