//! Projected Gauss–Seidel on the dense dual:
//!
//! ```text
//! λᵢ ← max(0, λᵢ − ω (H λ − d)ᵢ / Hᵢᵢ),   i = 1 … m, in order,
//! ```
//!
//! keeping the gradient w = H λ − d up to date with one column of H per changed λᵢ (inactive
//! rows, whose λᵢ stays 0, cost O(1)).  A sweep costs O(m · changed rows) while the full KKT
//! check costs a solve with the factor, so the periodic checks are spaced to take at most about
//! a tenth of the sweeping time; in between, the exact dual gradient w = g − B x(λ) decides when
//! to check early.  With a kernel, H and d are the augmented-Lagrangian
//! ones of [`crate::dual`].

use std::time::{Duration, Instant};

use signorini_core::qp::QpStatus;

use crate::dual::{DualData, Outcome};
use crate::error::DualError;
use crate::hessian::{dual_hessian, DenseSym};
use crate::monitor::{finish_at_limit, Monitor, Next};
use crate::settings::DualSettings;

/// Runs projected Gauss–Seidel until the monitor stops it.
pub fn solve(
    data: &mut DualData<'_>,
    settings: &DualSettings,
    monitor: &mut Monitor<'_>,
) -> Result<Outcome, DualError> {
    let mut hessian = dual_hessian(data, settings)?;
    if data.floating() {
        let norm = hessian.largest_eigenvalue(settings.power_iterations);
        data.set_penalty(norm, settings.equality_penalty);
        hessian.add_penalty(&data.modes, data.penalty);
    }
    let dual_load = data.dual_load();
    let mut inner_load = data.inner_load(&dual_load);
    let diagonal = safe_diagonal(&hessian);
    let m = data.rows();
    let mut lambda = vec![0.0; m];
    let mut gradient = residual(&hessian, &lambda, &inner_load);
    monitor.calibrate(&data.base);
    let mut iter = 0;
    let mut sweep_time = Duration::ZERO;
    loop {
        if let Some((status, message)) = monitor.limit(iter) {
            return Ok(finish_at_limit(
                data,
                monitor.tol(),
                iter,
                lambda,
                status,
                message,
            ));
        }
        let started = Instant::now();
        sweep(
            &hessian,
            &diagonal,
            settings.relaxation,
            &mut lambda,
            &mut gradient,
        );
        sweep_time += started.elapsed();
        iter += 1;
        let estimate = monitor.estimate(&lambda, &gradient);
        if !monitor.due(iter, estimate) {
            continue;
        }
        let started = Instant::now();
        let x = data.primal(&lambda);
        let check_time = started.elapsed();
        // Keep the periodic checks (one solve each) under ~10 % of the sweeping time.
        let per_sweep = sweep_time.as_secs_f64() / iter as f64;
        if per_sweep > 0.0 {
            let period = (10.0 * check_time.as_secs_f64() / per_sweep).ceil();
            monitor.stretch_period(period.min(1e6) as usize);
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
                inner_load = data.inner_load(&dual_load);
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
        gradient = residual(&hessian, &lambda, &inner_load);
    }
}

/// w = H λ − d.
fn residual(hessian: &DenseSym, lambda: &[f64], load: &[f64]) -> Vec<f64> {
    let mut w = hessian.mul(lambda);
    w.iter_mut().zip(load).for_each(|(wi, di)| *wi -= di);
    w
}

/// Hᵢᵢ, with zero (or negative round-off) entries raised to a tiny fraction of the largest one
/// so that an empty contact row never divides by zero.
fn safe_diagonal(hessian: &DenseSym) -> Vec<f64> {
    let diag: Vec<f64> = (0..hessian.size).map(|i| hessian.diag(i)).collect();
    let floor = 1e-14 * diag.iter().copied().fold(0.0, f64::max);
    diag.into_iter()
        .map(|v| v.max(floor).max(f64::MIN_POSITIVE))
        .collect()
}

/// One forward sweep; `gradient` = H λ − d is kept in step.
fn sweep(
    hessian: &DenseSym,
    diagonal: &[f64],
    omega: f64,
    lambda: &mut [f64],
    gradient: &mut [f64],
) {
    for i in 0..lambda.len() {
        let updated = (lambda[i] - omega * gradient[i] / diagonal[i]).max(0.0);
        let delta = updated - lambda[i];
        if delta != 0.0 {
            lambda[i] = updated;
            gradient
                .iter_mut()
                .zip(hessian.col(i))
                .for_each(|(w, h)| *w += delta * h);
        }
    }
}
