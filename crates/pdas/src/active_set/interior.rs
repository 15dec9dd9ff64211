//! The globalised iteration, taken over from the plain one when its sets flip: a primal–dual
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
//! factor each step.  As soon as the set the iterate predicts, { i : λᵢ Xᵢ > sᵢ F } (forces and
//! gaps in the units of the KKT residuals), is the same twice in a row, that set is solved
//! exactly (its KKT system, unregularised through refinement, as in the plain iteration) and
//! accepted when it reproduces itself and meets the tolerance: the interior iterate only has
//! to find the set, never to be accurate itself.

use std::time::Instant;

use signorini_qp::{dot, kkt_residuals_with, mat_t_vec, mat_vec, QpStatus};

use super::{count, ActiveSet, Outcome, Phase1};
use crate::refine::{first_solve, refine, Limits};
use crate::update::SetSolver;

/// Fraction of the distance to the boundary an interior step may go.
const TO_BOUNDARY: f64 = 0.995;

/// The start's centring shift, as a multiple of Mehrotra's (½ ŝᵀλ̂ / Σλ̂ on the gaps,
/// ½ ŝᵀλ̂ / Σŝ on the forces): a start well inside the interior.  Iterations to solved on
/// strip-partial floating / clamped at its left end (7 of them plain active-set steps):
/// ×1 → 23 / 54, ×10² → 15 / 34, ×10³ → 14 / 28, ×10⁴ → 14 / 28, ×10⁵ → 16 / 29.
/// (η = 0.9 or 0.999 for [`TO_BOUNDARY`] instead of 0.995: 25 and 23 at ×1.)
const START_CENTRING: f64 = 1e3;

impl ActiveSet<'_> {
    /// Runs the interior-point iteration from (x, λ) until the iteration cap, the time limit
    /// or an accepted crossover.
    pub(super) fn interior(
        &mut self,
        mut x: Vec<f64>,
        multipliers: &[f64],
        phase1: Phase1,
        max_iter: usize,
    ) -> Outcome {
        let p = self.problem;
        let (n, m) = (p.dofs(), p.rows());
        let Phase1 {
            mut iteration,
            mut best,
            mut best_worst,
        } = phase1;
        let force = self.scales.force;
        let rows = self.scales.rows.clone();
        // Mehrotra's start in scaled variables ŝ = s / X, λ̂ = λ / F.
        let bx = mat_vec(&p.constraints, &x);
        let mut s: Vec<f64> = p.gap.iter().zip(&bx).map(|(g, b)| g - b).collect();
        let mut lambda: Vec<f64> = multipliers.to_vec();
        let shift_s = (-1.5 * (0..m).map(|i| s[i] / rows[i]).fold(0.0, f64::min)).max(0.0);
        let shift_l = (-1.5 * lambda.iter().map(|l| l / force).fold(0.0, f64::min)).max(0.0);
        for i in 0..m {
            s[i] += shift_s * rows[i];
            lambda[i] += shift_l * force;
        }
        let product: f64 = (0..m).map(|i| s[i] / rows[i] * lambda[i] / force).sum();
        let sum_s: f64 = (0..m).map(|i| s[i] / rows[i]).sum();
        let sum_l: f64 = lambda.iter().map(|l| l / force).sum();
        let (extra_s, extra_l) = if product > 0.0 {
            (
                0.5 * product / sum_l.max(f64::MIN_POSITIVE),
                0.5 * product / sum_s.max(f64::MIN_POSITIVE),
            )
        } else {
            (1.0, 1.0)
        };
        let (extra_s, extra_l) = (START_CENTRING * extra_s, START_CENTRING * extra_l);
        for i in 0..m {
            s[i] += extra_s.max(1e-8) * rows[i];
            lambda[i] += extra_l.max(1e-8) * force;
        }
        let floor = 1e-3 * self.delta();
        let mut previous: Option<Vec<bool>> = None;
        let mut tried: Vec<Vec<bool>> = Vec::new();
        let mut steps = 0;
        let mut crossovers = 0;
        let mut first_mu: Option<f64> = None;
        loop {
            if iteration >= max_iter || self.out_of_time() {
                let (status, why) = if iteration >= max_iter {
                    (QpStatus::MaxIterations, format!("{max_iter} iterations"))
                } else {
                    (QpStatus::TimeLimit, "time limit reached".to_string())
                };
                let message = format!(
                    "{why} without meeting the tolerance (interior-point iteration after the active-set steps flipped: {steps} interior steps; best KKT residuals {best_worst:.1e})"
                );
                return self.finish(best, status, iteration, message);
            }
            iteration += 1;
            steps += 1;
            let mut r_d = mat_vec(&p.stiffness, &x);
            let btl = mat_t_vec(&p.constraints, &lambda);
            for j in 0..n {
                r_d[j] += btl[j] - p.load[j];
            }
            let bx = mat_vec(&p.constraints, &x);
            let r_p: Vec<f64> = (0..m).map(|i| bx[i] + s[i] - p.gap[i]).collect();
            let mu = dot(&s, &lambda) / m.max(1) as f64;
            let diagonal: Vec<f64> = (0..m).map(|i| (s[i] / lambda[i]).max(floor)).collect();
            let clock = Instant::now();
            self.kkt.set_diagonal(0.0, &diagonal);
            if let Err(e) = self.factor_values(clock) {
                return self.finish(best, QpStatus::NumericalError, iteration, e.to_string());
            }
            self.cache.clear();
            // Predictor (affine scaling).
            let solve = |this: &mut Self, tail: &[f64]| -> (Vec<f64>, Vec<f64>, Vec<f64>) {
                let mut z: Vec<f64> = r_d.iter().map(|v| -v).chain(tail.iter().copied()).collect();
                this.factor.solve_in_place(&mut z);
                let dl = z.split_off(n);
                let bdx = mat_vec(&p.constraints, &z);
                let ds: Vec<f64> = (0..m).map(|i| -r_p[i] - bdx[i]).collect();
                (z, dl, ds)
            };
            let tail: Vec<f64> = (0..m).map(|i| -r_p[i] + s[i]).collect();
            let (_, dl_a, ds_a) = solve(self, &tail);
            let alpha_a = max_step(&s, &ds_a).min(max_step(&lambda, &dl_a)).min(1.0);
            let mu_a = (0..m)
                .map(|i| (s[i] + alpha_a * ds_a[i]) * (lambda[i] + alpha_a * dl_a[i]))
                .sum::<f64>()
                / m.max(1) as f64;
            let sigma = (mu_a / mu).clamp(0.0, 1.0).powi(3);
            // Corrector.
            let tail: Vec<f64> = (0..m)
                .map(|i| -r_p[i] + s[i] + (ds_a[i] * dl_a[i] - sigma * mu) / lambda[i])
                .collect();
            let (dx, dl, ds) = solve(self, &tail);
            let alpha = (TO_BOUNDARY * max_step(&s, &ds).min(max_step(&lambda, &dl))).min(1.0);
            if alpha.is_nan() || alpha <= 0.0 || dx.iter().chain(&dl).any(|v| !v.is_finite()) {
                let message = format!(
                    "the interior-point step failed (step length {alpha:.1e}) after {steps} interior steps; best KKT residuals {best_worst:.1e}"
                );
                return self.finish(best, QpStatus::Inaccurate, iteration, message);
            }
            x.iter_mut().zip(&dx).for_each(|(v, d)| *v += alpha * d);
            s.iter_mut().zip(&ds).for_each(|(v, d)| *v += alpha * d);
            lambda
                .iter_mut()
                .zip(&dl)
                .for_each(|(v, d)| *v += alpha * d);
            let set: Vec<bool> = (0..m).map(|i| lambda[i] * rows[i] > s[i] * force).collect();
            if self.options.verbose {
                eprintln!(
                    "pdas: iteration {iteration}: interior step, μ {mu:.2e}, σ {sigma:.2e}, α {alpha:.3}, {} rows predicted active",
                    count(&set)
                );
            }
            let repeated = previous.as_ref() == Some(&set);
            previous = Some(set.clone());
            let mu0 = *first_mu.get_or_insert(mu);
            // No crossover before μ has fallen tenfold: the first sets are the start's.
            if !repeated || tried.contains(&set) || mu > 0.1 * mu0 {
                continue;
            }
            // Crossover: exact solves from the predicted set on, by the active-set rule for
            // as long as the number of changes falls (the plain iteration's local regime).
            let mut set = set;
            let mut last_changes = usize::MAX;
            loop {
                tried.push(set.clone());
                if iteration >= max_iter || self.out_of_time() {
                    break;
                }
                iteration += 1;
                crossovers += 1;
                let delta = self.delta();
                if let Err(e) = self.factorise_with(&set, delta, 0.0) {
                    return self.finish(best, QpStatus::NumericalError, iteration, e.to_string());
                }
                let limits = Limits {
                    max_steps: self.settings.refinement_steps,
                    target: self.settings.refinement_target * self.options.tol,
                    deadline: self.deadline(),
                };
                let mut solver = SetSolver {
                    factor: &mut self.factor,
                    update: None,
                };
                let mut solution = first_solve(p, &set, &mut solver);
                refine(p, &self.scales, &set, &mut solver, &mut solution, &limits);
                self.refinement_steps += solution.steps;
                let next = self.next_set(&solution);
                let clamped: Vec<f64> = solution.multipliers.iter().map(|l| l.max(0.0)).collect();
                let r = kkt_residuals_with(p, &self.scales, &solution.x, &clamped);
                let worst = r.worst();
                let changes = next.iter().zip(&set).filter(|(a, b)| a != b).count();
                if self.options.verbose {
                    eprintln!(
                    "pdas: iteration {iteration}: crossover to {} active rows, KKT {worst:.1e}, {changes} changes",
                    count(&set)
                );
                }
                let finite = solution
                    .x
                    .iter()
                    .chain(&solution.multipliers)
                    .all(|v| v.is_finite());
                let candidate = Outcome {
                    x: solution.x,
                    multipliers: clamped,
                    status: QpStatus::Solved,
                    iterations: iteration,
                    message: String::new(),
                };
                if finite && changes == 0 && r.meet(self.options.tol) {
                    let message = format!(
                    "{} active rows (the active-set steps flipped; {steps} interior-point steps, then {crossovers} exact solves from the set they found)",
                    count(&set)
                );
                    return self.finish(candidate, QpStatus::Solved, iteration, message);
                }
                if finite && worst < best_worst {
                    best_worst = worst;
                    best = candidate;
                }
                if solution.timed_out {
                    return self.finish(
                        best,
                        QpStatus::TimeLimit,
                        iteration,
                        "time limit reached during refinement".into(),
                    );
                }
                if changes == 0 || changes > last_changes || tried.contains(&next) {
                    break;
                }
                last_changes = changes;
                set = next;
            }
        }
    }
}

/// The largest α ≤ ∞ with v + α dv ≥ 0 (v > 0).
fn max_step(v: &[f64], dv: &[f64]) -> f64 {
    v.iter()
        .zip(dv)
        .filter(|(_, d)| **d < 0.0)
        .map(|(a, d)| -a / d)
        .fold(f64::INFINITY, f64::min)
}
