//! Primal–dual active set (a semismooth Newton method on min(λ, ν/σ) = 0) on the dense dual:
//!
//! ```text
//! F = { i : λᵢ − νᵢ / Hᵢᵢ > 0 },   λ_Z = 0,
//! [ H_FF  G_Fᵀ ] [ λ_F ]   [ d_F ]
//! [ G_F    0   ] [  μ  ] = [  e  ],    ν = H λ − d + Gᵀ μ,
//! ```
//!
//! repeated until F no longer changes; then (λ, μ) is exact up to round-off and
//! x = A⁺(f − Bᵀλ) − R μ.  Each step costs one dense factorisation of order |F| (+ k).

use std::collections::HashSet;

use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use signorini_core::qp::QpStatus;

use crate::dual::{DualData, Outcome};
use crate::error::DualError;
use crate::hessian::{dual_hessian, DenseSym};
use crate::monitor::{finish_at_limit, Monitor, Next};
use crate::settings::DualSettings;

/// Runs the active-set method until the set repeats or the monitor stops it.
pub fn solve(
    data: &mut DualData<'_>,
    settings: &DualSettings,
    monitor: &mut Monitor<'_>,
) -> Result<Outcome, DualError> {
    let hessian = dual_hessian(data, settings)?;
    let load = data.dual_load();
    let m = data.rows();
    let k = data.modes.count();
    data.penalty = 0.0;
    let mut active: Vec<bool> = if data.floating() {
        vec![true; m]
    } else {
        load.iter().map(|d| *d > 0.0).collect()
    };
    let mut seen: HashSet<Vec<bool>> = HashSet::new();
    let mut lambda = vec![0.0; m];
    let mut iter = 0;
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
        seen.insert(active.clone());
        let Some((next_lambda, mu)) = newton_step(&hessian, &load, data, &active) else {
            return Ok(Outcome {
                x: data.base.clone(),
                multipliers: lambda,
                status: QpStatus::NumericalError,
                iterations: iter,
                message: format!(
                    "singular active-set system on {} rows (redundant contact rows, or a rigid mode the active contacts do not hold; k = {k})",
                    active.iter().filter(|a| **a).count()
                ),
            });
        };
        lambda = next_lambda;
        data.multiplier = mu;
        iter += 1;
        let mut reduced = hessian.mul(&lambda);
        reduced.iter_mut().zip(&load).for_each(|(r, d)| *r -= d);
        crate::kernel::add_coupling_t(&data.modes, &data.multiplier, &mut reduced);
        let next_active: Vec<bool> = (0..m)
            .map(|i| lambda[i] - reduced[i] / hessian.diag(i).max(f64::MIN_POSITIVE) > 0.0)
            .collect();
        let lambda_clipped: Vec<f64> = lambda.iter().map(|l| l.max(0.0)).collect();
        if next_active == active {
            let x = data.primal(&lambda_clipped);
            let (status, message) = match monitor.check(data, iter, &lambda_clipped, &x) {
                Next::Stop(status, message) => (status, message),
                _ => (
                    QpStatus::Inaccurate,
                    "active set settled but the KKT residuals miss the tolerance".to_string(),
                ),
            };
            return Ok(Outcome {
                x,
                multipliers: lambda_clipped,
                status,
                iterations: iter,
                message,
            });
        }
        if seen.contains(&next_active) {
            return Ok(finish_at_limit(
                data,
                monitor.tol(),
                iter,
                lambda_clipped,
                QpStatus::MaxIterations,
                "active set cycles".to_string(),
            ));
        }
        active = next_active;
    }
}

/// A dense factorisation of the (shifted) Newton matrix.
enum Dense {
    /// Symmetric positive definite block (no kernel).
    Cholesky(faer::linalg::solvers::Llt<f64>),
    /// Indefinite bordered system, or a failed Cholesky.
    Lu(faer::linalg::solvers::PartialPivLu<f64>),
}

impl Dense {
    fn solve(&self, rhs: &mut Mat<f64>) {
        match self {
            Dense::Cholesky(llt) => llt.solve_in_place(rhs.as_mut()),
            Dense::Lu(lu) => lu.solve_in_place(rhs.as_mut()),
        }
    }
}

/// Relative Tikhonov shift of the active block (× max Hᵢᵢ); removed again by refinement.
const SHIFT: f64 = 1e-12;

/// Refinement steps against the unshifted system.
const REFINEMENT_STEPS: usize = 3;

/// Solves the Newton system on the active rows; `None` if it is singular.
///
/// The active block is factored with a tiny shift ε I (ε = `SHIFT` · max Hᵢᵢ), so that
/// duplicated or dependent contact rows (a singular but consistent H_FF) do not break the
/// factorisation; a few steps of iterative refinement against the unshifted matrix then remove
/// the shift's effect.
fn newton_step(
    hessian: &DenseSym,
    load: &[f64],
    data: &DualData<'_>,
    active: &[bool],
) -> Option<(Vec<f64>, Vec<f64>)> {
    let rows: Vec<usize> = (0..active.len()).filter(|&i| active[i]).collect();
    let p = rows.len();
    let k = data.modes.count();
    let size = p + k;
    let max_diag = (0..hessian.size)
        .map(|i| hessian.diag(i))
        .fold(0.0, f64::max);
    let shift = SHIFT * max_diag;
    let matrix = Mat::<f64>::from_fn(size, size, |a, b| match (a < p, b < p) {
        (true, true) => hessian.col(rows[b])[rows[a]],
        (true, false) => data.modes.coupling[b - p][rows[a]],
        (false, true) => data.modes.coupling[a - p][rows[b]],
        (false, false) => 0.0,
    });
    let shifted = Mat::<f64>::from_fn(size, size, |a, b| {
        matrix[(a, b)] + if a == b && a < p { shift } else { 0.0 }
    });
    let rhs = Mat::<f64>::from_fn(size, 1, |a, _| {
        if a < p {
            load[rows[a]]
        } else {
            data.modes.load[a - p]
        }
    });
    let solver = if k == 0 {
        match shifted.llt(Side::Lower) {
            Ok(llt) => Dense::Cholesky(llt),
            Err(_) => Dense::Lu(shifted.partial_piv_lu()),
        }
    } else {
        Dense::Lu(shifted.partial_piv_lu())
    };
    let mut solution = rhs.clone();
    solver.solve(&mut solution);
    for _ in 0..REFINEMENT_STEPS {
        let mut residual = &rhs - &matrix * &solution;
        solver.solve(&mut residual);
        solution += residual;
    }
    if (0..size).any(|a| !solution[(a, 0)].is_finite()) {
        return None;
    }
    let mut lambda = vec![0.0; active.len()];
    for (a, &i) in rows.iter().enumerate() {
        lambda[i] = solution[(a, 0)];
    }
    let mu = (0..k).map(|j| solution[(p + j, 0)]).collect();
    Some((lambda, mu))
}
