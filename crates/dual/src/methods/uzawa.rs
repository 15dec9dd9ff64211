//! Uzawa: projected gradient on the dual with one solve of the cached factor per step,
//!
//! ```text
//! x = A⁻¹(f − Bᵀλ),   λ ← max(0, λ + ρ (B x − g)),   ρ = step_factor / L̂,
//! ```
//!
//! (on a box row the projection is onto [−s, s] instead: [`super::intervals`]).
//!
//! L̂ ≥ λ_max(H) from power iteration (one solve per power step).  With acceleration the step is
//! taken from the extrapolated point y = λₖ + βₖ(λₖ − λₖ₋₁) (FISTA, βₖ = (tₖ − 1)/tₖ₊₁) and the
//! momentum restarts whenever (y − λₖ₊₁)ᵀ(λₖ₊₁ − λₖ) > 0 (O'Donoghue–Candès gradient
//! restart).  Because x is affine in λ, x(y) is the same combination of x(λₖ) and x(λₖ₋₁): still
//! one solve per step.

use signorini_qp::{dot, mat_vec, QpStatus};

use super::intervals;
use crate::dual::{DualData, Outcome};
use crate::error::DualError;
use crate::hessian::power_iteration;
use crate::monitor::{finish_at_limit, Monitor, Next};
use crate::settings::DualSettings;

/// Runs (accelerated) Uzawa until the monitor stops it.
pub fn solve(
    data: &mut DualData<'_>,
    settings: &DualSettings,
    monitor: &mut Monitor<'_>,
) -> Result<Outcome, DualError> {
    let m = data.rows();
    let hessian_norm = power_iteration(m, settings.power_iterations, |v| {
        // Past the time limit: a zero product ends the power iteration (the main loop then
        // stops at once), so the overshoot is at most one solve.
        if monitor.out_of_time() {
            return vec![0.0; v.len()];
        }
        // H v = B A⁺ Bᵀ v = B (A⁺ f − A⁺(f − Bᵀ v)).
        let free = data.free_part(v);
        let diff: Vec<f64> = data.base().iter().zip(&free).map(|(b, u)| b - u).collect();
        mat_vec(&data.problem.constraints, &diff)
    });
    data.set_penalty(hessian_norm, settings.equality_penalty);
    let lipschitz = hessian_norm + data.penalty * data.modes.coupling_norm_sq();
    // H = 0 (no row sees any free DOF): any step is as good; take the unit one.
    let lipschitz = if lipschitz > 0.0 { lipschitz } else { 1.0 };
    let step = settings.step_factor / lipschitz;

    let bounds = intervals::of(data.problem);
    let mut lambda = vec![0.0; m];
    let mut previous = lambda.clone();
    let mut free = data.base().to_vec();
    let mut free_previous = free.clone();
    let mut momentum = 1.0_f64;
    monitor.calibrate(data.base());
    let mut iter = 0;
    loop {
        if let Some((status, message)) = monitor.limit(iter) {
            return Ok(finish_at_limit(
                data, monitor, iter, lambda, status, message,
            ));
        }
        let (beta, next_momentum) = if settings.accelerate {
            let t = 0.5 * (1.0 + (1.0 + 4.0 * momentum * momentum).sqrt());
            ((momentum - 1.0) / t, t)
        } else {
            (0.0, 1.0)
        };
        let y = extrapolate(&lambda, &previous, beta);
        let free_y = extrapolate(&free, &free_previous, beta);
        let gradient_y = data.dual_gradient(&data.primal_from(free_y, &y));
        let next: Vec<f64> = y
            .iter()
            .zip(&gradient_y)
            .zip(&bounds)
            .map(|((yi, wi), b)| intervals::project(yi - step * wi, *b))
            .collect();
        let restart = {
            let back: Vec<f64> = y.iter().zip(&next).map(|(a, b)| a - b).collect();
            let forward: Vec<f64> = next.iter().zip(&lambda).map(|(a, b)| a - b).collect();
            dot(&back, &forward) > 0.0
        };
        momentum = if restart { 1.0 } else { next_momentum };
        previous = std::mem::replace(&mut lambda, next);
        free_previous = std::mem::replace(&mut free, data.free_part(&lambda));
        iter += 1;

        let x = data.primal_from(free.clone(), &lambda);
        let estimate = monitor.estimate(&lambda, &data.dual_gradient(&x));
        if !monitor.due(iter, estimate) {
            continue;
        }
        match monitor.check(data, iter, &lambda, &x) {
            Next::Continue => {}
            Next::UpdateMultiplier => {
                if let Some(message) = data.update_multiplier(&lambda) {
                    return Ok(Outcome {
                        x,
                        multipliers: lambda,
                        status: QpStatus::DualInfeasible,
                        iterations: iter,
                        message,
                    });
                }
                previous.clone_from(&lambda);
                free_previous.clone_from(&free);
                momentum = 1.0;
            }
            Next::Stop(status, message) => {
                return Ok(Outcome {
                    x,
                    multipliers: lambda,
                    status,
                    iterations: iter,
                    message,
                })
            }
        }
    }
}

/// a + β (a − b).
fn extrapolate(current: &[f64], previous: &[f64], beta: f64) -> Vec<f64> {
    if beta == 0.0 {
        return current.to_vec();
    }
    current
        .iter()
        .zip(previous)
        .map(|(a, b)| a + beta * (a - b))
        .collect()
}
