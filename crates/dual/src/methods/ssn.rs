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
//! and (λ_F, μ) is corrected by the already factored dense system applied to (r_F, r_e), until
//! the (scaled) residual stops decreasing: first with plain sparse solves, and only when those
//! miss the tolerance again with solves corrected in double-double arithmetic.  The dense factor only has to be a good
//! preconditioner; the accuracy comes from the sparse residual.  The next active set is decided
//! from the refined λ and the exact dual gradient ν = g − B x.

use std::collections::HashSet;

use signorini_qp::{norm_inf, QpStatus};

use super::newton::{lumped_compliance, DenseBlock, MatrixFreeBlock};
use crate::dual::{two_sum, DualData, Outcome};
use crate::error::DualError;
use crate::hessian::{dense_bytes, dual_hessian};
use crate::monitor::{finish_at_limit, Monitor, Next};
use crate::settings::DualSettings;

/// At most this many corrections per Newton step (each costs one sparse solve).
const MAX_REFINEMENT: usize = 30;

/// Mixed-precision corrections of each sparse solve x(λ) (see
/// [`DualData::free_part_accurate`]).
const ACCURATE_SOLVE_CORRECTIONS: usize = 4;

/// A correction is kept going only while it shrinks the scaled residual by at least this
/// factor (slower contraction means round-off has been reached).
const CONTRACTION: f64 = 0.5;

/// From this many active-set steps on, an iterate whose set still moves is checked against
/// the tolerance (one sparse solve) before the next step: the set can move on round-off alone.
const CHECK_MOVING_FROM: usize = 3;

/// Runs the active-set method until the set repeats or the monitor stops it.
pub fn solve(
    data: &mut DualData<'_>,
    settings: &DualSettings,
    monitor: &mut Monitor<'_>,
) -> Result<Outcome, DualError> {
    let m = data.rows();
    let k = data.modes.count();
    data.penalty = 0.0;
    if let Some(message) = data.modes.farkas_direction() {
        return Ok(stopped(data, QpStatus::DualInfeasible, message));
    }
    // Besides H: the dense Newton matrix, its shifted copy and their factor.
    let fits =
        signorini_qp::memory::check_fits("dual-ssn", String::new, dense_bytes(data, settings, 3.0))
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
    let mode = if hessian.is_some() {
        "dense Newton steps"
    } else {
        "matrix-free Newton steps (projected CG through the sparse factor)"
    };
    let mut active: Vec<bool> = if data.floating() {
        vec![true; m]
    } else {
        load.iter().map(|d| *d > 0.0).collect()
    };
    let mut seen: HashSet<Vec<bool>> = HashSet::new();
    let mut lambda = vec![0.0; m];
    let mut iter = 0;
    let mut refinements = 0;
    // Cheap steps while the set moves (dense: the dense step alone, no sparse solve;
    // matrix-free: plain sparse solves in the refinement); once it settles, the same set is
    // solved again, refined with the mixed-precision solves, and decided anew.
    let mut stall = Stall::default();
    let mut dense_phase = hessian.is_some();
    let mut accurate = false;
    let mut redo = false;
    loop {
        if let Some((status, message)) = monitor.limit(iter) {
            return Ok(finish_at_limit(
                data, monitor, iter, lambda, status, message,
            ));
        }
        seen.insert(active.clone());
        let out_of_time = || monitor.out_of_time();
        let step = match &hessian {
            Some(h) if dense_phase => {
                // While the set moves: the dense step alone, its gradient from the dense H (no
                // sparse solve); the settled set is solved again, refined.
                let block = DenseBlock::factor(h, &data.modes, &active);
                dense_step(h, &block, data, &load)
            }
            Some(h) => {
                let block = DenseBlock::factor(h, &data.modes, &active);
                refined_step(
                    data,
                    &block.rows,
                    &|r, e| block.solve(r, e),
                    &load,
                    monitor,
                    accurate,
                )
            }
            None => {
                MatrixFreeBlock::new(data, &active, &diagonal, &out_of_time).and_then(|block| {
                    refined_step(
                        data,
                        &block.rows,
                        &|r, e| block.solve(r, e),
                        &load,
                        monitor,
                        accurate,
                    )
                })
            }
        };
        let Some(step) = step else {
            let mut out = stopped(
                data,
                QpStatus::NumericalError,
                format!(
                    "singular active-set system on {} rows (redundant contact rows, or a rigid mode the active contacts do not hold; k = {k})",
                    active.iter().filter(|a| **a).count()
                ),
            );
            out.iterations = iter;
            return Ok(out);
        };
        refinements += step.refinements;
        lambda = step.lambda;
        data.multiplier = step.mu;
        if !redo {
            iter += 1;
        }
        redo = false;
        let next_active: Vec<bool> = (0..m)
            .map(|i| lambda[i] - step.gradient[i] / diagonal[i] > 0.0)
            .collect();
        if next_active == active && dense_phase {
            // Settled on the dense steps: solve the set again against the sparse residual.
            dense_phase = false;
            redo = true;
            continue;
        }
        if next_active == active && !accurate {
            // Plain refinement is enough for a well-conditioned dual (one or two sparse
            // solves); only when it misses the tolerance is the set solved with the
            // mixed-precision solves (five sparse solves per evaluation).
            let solved = !lambda.iter().any(|l| *l < 0.0)
                && matches!(
                    monitor.check(data, iter, &lambda, &step.x),
                    Next::Stop(QpStatus::Solved, _)
                );
            if !solved {
                accurate = true;
                redo = true;
                continue;
            }
        }
        if next_active == active {
            let clipped = lambda.iter().any(|l| *l < 0.0);
            let lambda_clipped: Vec<f64> = lambda.iter().map(|l| l.max(0.0)).collect();
            let x = if clipped {
                data.primal_at(&lambda_clipped, &data.multiplier)
            } else {
                step.x
            };
            let (status, message) = match monitor.check(data, iter, &lambda_clipped, &x) {
                Next::Stop(status, message) => (status, message),
                _ => (
                    QpStatus::Inaccurate,
                    monitor.explain(format!(
                        "active set settled but the KKT residuals miss the tolerance (refined primal residual {:.1e} after {} corrections)",
                        step.residual, step.refinements
                    )),
                ),
            };
            return Ok(Outcome {
                x,
                multipliers: lambda_clipped,
                status,
                iterations: iter,
                message: format!(
                    "{message}; {iter} active-set steps ({mode}), {refinements} refinement solves"
                ),
            });
        }
        // The set can move on round-off alone while the iterate already meets the tolerance:
        // a body 1e30 times softer than its neighbours makes νᵢ / Hᵢᵢ noise around zero, and each
        // new set costs a dense factorisation of up to m rows.  From a few steps on, one sparse
        // solve checks the iterate first (cheaper than that factorisation).
        if iter >= CHECK_MOVING_FROM {
            let (checked, worst) = checked_iterate(data, monitor, iter, &lambda);
            if checked.status == QpStatus::Solved {
                return Ok(Outcome {
                    message: format!(
                        "{}; the iterate met the tolerance while the active set still moved (on round-off); {iter} active-set steps ({mode}), {refinements} refinement solves",
                        checked.message
                    ),
                    ..checked
                });
            }
            let changes = (0..m).filter(|&i| next_active[i] != active[i]).count();
            if let Some(why) = stall.observe(iter, changes, worst) {
                return Ok(Outcome {
                    message: format!(
                        "{}; {why}; {iter} active-set steps ({mode}), {refinements} refinement solves",
                        checked.message
                    ),
                    ..checked
                });
            }
        }
        if seen.contains(&next_active) {
            let lambda_clipped = lambda.iter().map(|l| l.max(0.0)).collect();
            return Ok(finish_at_limit(
                data,
                monitor,
                iter,
                lambda_clipped,
                QpStatus::MaxIterations,
                "active set cycles".to_string(),
            ));
        }
        active = next_active;
    }
}

/// Steps without progress after which a set that still moves is given up: [`Stall`].
const STALL_STEPS: usize = 10;

/// Progress of a moving active set, from [`CHECK_MOVING_FROM`] on: a step makes progress when
/// fewer rows change than ever before, or the checked iterate's worst KKT residual falls below
/// half its best.  A set that makes neither for [`STALL_STEPS`] steps is moving on round-off
/// (or cycling through sets too many to remember), not towards an answer: the iterate is given
/// as it is, `inaccurate`, instead of dense factorisations to the iteration limit (a 1e-5-thin
/// strip with m = 903: 100 000 steps, ~11 min).  The fixtures settle within 14 steps, each
/// making progress.
#[derive(Debug, Default)]
struct Stall {
    /// Fewest rows that changed in a step, the smallest worst residual, and the last step that
    /// improved either.
    best: Option<(usize, f64, usize)>,
}

impl Stall {
    /// Records step `iter` (`changes` rows changed, worst residual `worst`); says why to stop
    /// when it is time.
    fn observe(&mut self, iter: usize, changes: usize, worst: f64) -> Option<String> {
        let Some((fewest, lowest, at)) = self.best else {
            self.best = Some((changes, worst, iter));
            return None;
        };
        if changes < fewest || worst < 0.5 * lowest {
            self.best = Some((changes.min(fewest), worst.min(lowest), iter));
            return None;
        }
        (iter - at >= STALL_STEPS).then(|| {
            format!(
                "stalled: the active set still moves ({changes} rows this step, never fewer than {fewest}) and the residual has not halved its best ({lowest:.1e}) since step {at}"
            )
        })
    }
}

/// The iterate λ (clipped at zero) as an answer, `solved` when its KKT residuals meet the
/// tolerance (else `inaccurate`), with the worst residual.
fn checked_iterate(
    data: &DualData<'_>,
    monitor: &Monitor<'_>,
    iter: usize,
    lambda: &[f64],
) -> (Outcome, f64) {
    let clipped: Vec<f64> = lambda.iter().map(|l| l.max(0.0)).collect();
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

/// The unrefined dense Newton step: (λ_F, μ) from the factored block, and the gradient
/// H λ − d + Gᵀ μ from the dense H (x is left empty: the step only decides the next set).
fn dense_step(
    hessian: &crate::hessian::DenseSym,
    block: &DenseBlock,
    data: &DualData<'_>,
    load: &[f64],
) -> Option<Step> {
    let rhs: Vec<f64> = block.rows.iter().map(|&i| load[i]).collect();
    let (lambda_f, mu) = block.solve(&rhs, &data.modes.load)?;
    let mut lambda = vec![0.0; data.rows()];
    for (&i, l) in block.rows.iter().zip(&lambda_f) {
        lambda[i] = *l;
    }
    let mut gradient = hessian.mul(&lambda);
    gradient.iter_mut().zip(load).for_each(|(w, d)| *w -= d);
    crate::kernel::add_coupling_t(&data.modes, &mu, &mut gradient);
    if gradient.iter().chain(&lambda).any(|v| !v.is_finite()) {
        return None;
    }
    Some(Step {
        lambda,
        mu,
        x: Vec::new(),
        gradient,
        residual: f64::NAN,
        refinements: 0,
    })
}

/// A finite answer (x = A⁺f) with a verdict and no iterations.
fn stopped(data: &DualData<'_>, status: QpStatus, message: String) -> Outcome {
    Outcome {
        x: data.base.clone(),
        multipliers: vec![0.0; data.rows()],
        status,
        iterations: 0,
        message,
    }
}

/// One Newton step, refined.
#[derive(Debug)]
struct Step {
    lambda: Vec<f64>,
    mu: Vec<f64>,
    /// x = A⁺(f − Bᵀλ) − R μ.
    x: Vec<f64>,
    /// g − B x = H λ − d + Gᵀ μ (exact up to one sparse solve's round-off).
    gradient: Vec<f64>,
    /// The scaled primal residual left.
    residual: f64,
    /// Corrections taken.
    refinements: usize,
}

/// The primal point of (λ, μ) and its residuals on the active rows.
struct Evaluated {
    x: Vec<f64>,
    gradient: Vec<f64>,
    rows: Vec<f64>,
    kernel: Vec<f64>,
    norm: f64,
}

fn evaluate(
    data: &DualData<'_>,
    rows: &[usize],
    lambda: &[f64],
    low: &[f64],
    mu: &[f64],
    corrections: usize,
) -> Evaluated {
    let free = data.free_part_accurate(lambda, Some(low), corrections);
    let x = data.primal_at_from(free, mu);
    let gradient = data.dual_gradient(&x);
    let residual_rows: Vec<f64> = rows.iter().map(|&i| -gradient[i]).collect();
    let kernel: Vec<f64> = data
        .modes
        .equality_residual(lambda)
        .iter()
        .map(|r| -r)
        .collect();
    let length = norm_inf(&x).max(f64::MIN_POSITIVE);
    let force = norm_inf(&data.problem.load)
        .max(norm_inf(&data.modes.load))
        .max(f64::MIN_POSITIVE);
    let norm = norm_inf(&residual_rows) / length + norm_inf(&kernel) / force;
    Evaluated {
        x,
        gradient,
        rows: residual_rows,
        kernel,
        norm,
    }
}

/// The solve of one active set's Newton system: (r_F, r_e) ↦ (λ_F, μ), `None` when singular.
type NewtonSolve<'a> = dyn Fn(&[f64], &[f64]) -> Option<(Vec<f64>, Vec<f64>)> + 'a;

/// Solves the Newton system on the active `rows` with `solve` (dense factor or matrix-free CG)
/// and refines it against the primal residual; `None` when the system is singular.
fn refined_step(
    data: &DualData<'_>,
    rows: &[usize],
    solve: &NewtonSolve<'_>,
    load: &[f64],
    monitor: &Monitor<'_>,
    accurate: bool,
) -> Option<Step> {
    let corrections = if accurate {
        ACCURATE_SOLVE_CORRECTIONS
    } else {
        0
    };
    let rows = rows.to_vec();
    let rhs: Vec<f64> = rows.iter().map(|&i| load[i]).collect();
    let (lambda_f, mut mu) = solve(&rhs, &data.modes.load)?;
    let mut lambda = vec![0.0; data.rows()];
    for (&i, l) in rows.iter().zip(&lambda_f) {
        lambda[i] = *l;
    }
    // λ is carried as the unevaluated sum λ + λ_lo, so that corrections far below ε‖λ‖ (the
    // dual of a thin body amplifies the rounding of λ by its condition number) still move x.
    let mut low = vec![0.0; data.rows()];
    let mut current = evaluate(data, &rows, &lambda, &low, &mu, corrections);
    let mut refinements = 0;
    while refinements < MAX_REFINEMENT && current.norm > 0.0 && !monitor.out_of_time() {
        let Some((dl, dmu)) = solve(&current.rows, &current.kernel) else {
            break;
        };
        let mut trial = lambda.clone();
        let mut trial_low = low.clone();
        for (&i, d) in rows.iter().zip(&dl) {
            let (hi, err) = two_sum(trial[i], d + trial_low[i]);
            trial[i] = hi;
            trial_low[i] = err;
        }
        let trial_mu: Vec<f64> = mu.iter().zip(&dmu).map(|(a, b)| a + b).collect();
        let next = evaluate(data, &rows, &trial, &trial_low, &trial_mu, corrections);
        if next.norm.is_nan() || next.norm >= current.norm {
            break;
        }
        refinements += 1;
        let enough = next.norm > CONTRACTION * current.norm;
        lambda = trial;
        low = trial_low;
        mu = trial_mu;
        current = next;
        if enough {
            break;
        }
    }
    Some(Step {
        lambda,
        mu,
        x: current.x,
        gradient: current.gradient,
        residual: current.norm,
        refinements,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_set_that_stops_improving_is_given_up_after_the_stall_steps() {
        // Steps 3, 4: progress (fewer changes, then a halved residual); from step 5 on neither
        // (more changes, a residual above half the best): given up at step 4 + STALL_STEPS.
        let mut stall = Stall::default();
        assert_eq!(stall.observe(3, 50, 1.0), None);
        assert_eq!(stall.observe(4, 40, 0.4), None);
        for iter in 5..4 + STALL_STEPS {
            assert_eq!(stall.observe(iter, 45, 0.3), None, "step {iter}");
        }
        let why = stall.observe(4 + STALL_STEPS, 45, 0.3).unwrap();
        assert!(why.contains("since step 4"), "{why}");
    }

    #[test]
    fn a_set_that_keeps_improving_is_never_given_up() {
        // Alternating progress: fewer changes, then a halved residual, for far longer than the
        // stall window.
        let mut stall = Stall::default();
        let mut residual = 1.0;
        for iter in 3..200 {
            if iter % 2 == 0 {
                residual *= 0.4;
            }
            let changes = 1_000 - iter;
            assert_eq!(stall.observe(iter, changes, residual), None, "step {iter}");
        }
    }
}
