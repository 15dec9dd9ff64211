//! The Newton step of dual-ssn on one active set: the dense step alone (while the set still
//! moves), or the step refined against the primal residual computed with the sparse A and B
//! (see the parent module's docs).

use signorini_qp::norm_inf;

use crate::dual::{two_sum, DualData};
use crate::hessian::DenseSym;
use crate::methods::newton::DenseBlock;
use crate::monitor::Monitor;

/// At most this many corrections per Newton step (each costs one sparse solve).
const MAX_REFINEMENT: usize = 30;

/// Mixed-precision corrections of each sparse solve x(λ) (see
/// [`DualData::free_part_accurate`]).
const ACCURATE_SOLVE_CORRECTIONS: usize = 4;

/// A correction is kept going only while it shrinks the scaled residual by at least this
/// factor (slower contraction means round-off has been reached).
const CONTRACTION: f64 = 0.5;

/// The unrefined dense Newton step: (λ_F, μ) from the factored block, and the gradient
/// H λ − d + Gᵀ μ from the dense H (x is left empty: the step only decides the next set).
/// `fixed` holds the multipliers of the inactive rows (0, or ±s on a slipping box row): they
/// move H_FI λ_I and G_I λ_I to the right-hand side.
pub(super) fn dense_step(
    hessian: &DenseSym,
    block: &DenseBlock,
    data: &DualData<'_>,
    load: &[f64],
    fixed: &[f64],
) -> Option<Step> {
    let known = hessian.mul(fixed);
    let rhs: Vec<f64> = block.rows.iter().map(|&i| load[i] - known[i]).collect();
    let kernel_rhs = kernel_rhs(data, fixed);
    let (lambda_f, mu) = block.solve(&rhs, &kernel_rhs)?;
    let mut lambda = fixed.to_vec();
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
        contraction: f64::NAN,
    })
}

/// e − G λ_I: the kernel equations' right-hand side with the fixed multipliers moved over.
fn kernel_rhs(data: &DualData<'_>, fixed: &[f64]) -> Vec<f64> {
    data.modes
        .equality_residual(fixed)
        .iter()
        .map(|r| -r)
        .collect()
}

/// One Newton step, refined.
#[derive(Debug)]
pub(super) struct Step {
    /// λ (off the active rows: 0, or ±s on a slipping box row).
    pub lambda: Vec<f64>,
    /// μ, the multipliers of the rigid-mode equations.
    pub mu: Vec<f64>,
    /// x = A⁺(f − Bᵀλ) − R μ.
    pub x: Vec<f64>,
    /// g − B x = H λ − d + Gᵀ μ (exact up to one sparse solve's round-off).
    pub gradient: Vec<f64>,
    /// The scaled primal residual left.
    pub residual: f64,
    /// Corrections taken.
    pub refinements: usize,
    /// The first correction's ratio of residuals (new / old; infinite when it did not shrink
    /// the residual or could not be solved, NaN when none was tried): how well the dense factor
    /// serves as a preconditioner of the exact Newton system.
    pub contraction: f64,
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
    // Measured on the stored A at x (what the KKT residuals judge), not as e − G λ.
    let kernel = data.modes.measured_residual(data.problem, &x, lambda, low);
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
pub(super) type NewtonSolve<'a> = dyn Fn(&[f64], &[f64]) -> Option<(Vec<f64>, Vec<f64>)> + 'a;

/// Solves the Newton system on the active `rows` with `solve` (dense factor or matrix-free CG)
/// and refines it against the primal residual; `None` when the system is singular.
pub(super) fn refined_step(
    data: &DualData<'_>,
    rows: &[usize],
    solve: &NewtonSolve<'_>,
    load: &[f64],
    monitor: &Monitor<'_>,
    (accurate, fixed): (bool, &[f64]),
) -> Option<Step> {
    let corrections = if accurate {
        ACCURATE_SOLVE_CORRECTIONS
    } else {
        0
    };
    let rows = rows.to_vec();
    // The first solve leaves out H_FI λ_I (not formed without H); the first correction, against
    // the primal residual at λ with its fixed part, brings it in exactly.
    let rhs: Vec<f64> = rows.iter().map(|&i| load[i]).collect();
    let (lambda_f, mut mu) = solve(&rhs, &kernel_rhs(data, fixed))?;
    let mut lambda = fixed.to_vec();
    for (&i, l) in rows.iter().zip(&lambda_f) {
        lambda[i] = *l;
    }
    // λ is carried as the unevaluated sum λ + λ_lo, so that corrections far below ε‖λ‖ (the
    // dual of a thin body amplifies the rounding of λ by its condition number) still move x.
    let mut low = vec![0.0; data.rows()];
    let mut current = evaluate(data, &rows, &lambda, &low, &mu, corrections);
    let mut refinements = 0;
    let mut contraction = f64::NAN;
    while refinements < MAX_REFINEMENT && current.norm > 0.0 && !monitor.out_of_time() {
        let Some((dl, dmu)) = solve(&current.rows, &current.kernel) else {
            if refinements == 0 {
                contraction = f64::INFINITY;
            }
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
        if refinements == 0 {
            // NaN (a non-finite residual) counts as no contraction.
            contraction = if next.norm < current.norm {
                next.norm / current.norm
            } else {
                f64::INFINITY
            };
        }
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
        contraction,
    })
}
