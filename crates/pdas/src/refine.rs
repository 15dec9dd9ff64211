//! One solve of the equality-constrained QP on an active set F, made accurate by iterative
//! refinement against the unregularised KKT system:
//!
//! ```text
//! r_x = f − A x − B_Fᵀ λ_F,   r_λ = g_F − B_F x,   (λᵢ = 0 off F)
//! [Δx; Δλ] = K⁻¹ [r_x; r_λ],  x += Δx,  λ_F += Δλ_F
//! ```
//!
//! with the products taken with the sparse A and B themselves, not with the regularised K.
//! The regularisations δ, ρ and the round-off of the factor only slow the iteration down; it
//! stops when the scaled residual stops decreasing (or is at round-off level), keeping the
//! best iterate.

use std::time::Instant;

use signorini_core::qp::{mat_t_vec, mat_vec, QpProblem, ResidualScales};

use crate::update::SetSolver;

/// A residual below this (scaled as below) is at round-off level: refinement stops.
pub const ROUND_OFF: f64 = 1e-15;

/// A step must reduce the residual at least by this factor to count as progress.
const PROGRESS: f64 = 0.5;

/// The refined solution of one active set.
#[derive(Debug, Clone)]
pub struct SetSolution {
    /// x.
    pub x: Vec<f64>,
    /// λ (zero off the set; may be negative on it).
    pub multipliers: Vec<f64>,
    /// Refinement steps taken (solves after the first).
    pub steps: usize,
    /// The final scaled residual max(‖r_x‖∞ / F, maxᵢ |r_λ,ᵢ| / Xᵢ).
    pub residual: f64,
    /// True when a time limit interrupted the refinement.
    pub timed_out: bool,
}

/// When refinement stops.
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// The most steps.
    pub max_steps: usize,
    /// Stop once the scaled residual is at most this.
    pub target: f64,
    /// No step after this instant.
    pub deadline: Option<Instant>,
}

/// Solves K z = [f; g_F] with the current factor, without refinement.
pub fn first_solve(
    problem: &QpProblem,
    scales: &ResidualScales,
    active: &[bool],
    solver: &mut SetSolver<'_>,
) -> SetSolution {
    let n = problem.dofs();
    let mut z: Vec<f64> = problem
        .load
        .iter()
        .copied()
        .chain(
            problem
                .gap
                .iter()
                .zip(active)
                .map(|(g, &on)| if on { *g } else { 0.0 }),
        )
        .collect();
    solver.solve_in_place(&mut z);
    clear_inactive(&mut z[n..], active);
    let (_, residual) = residual(problem, scales, active, &z);
    let multipliers = z.split_off(n);
    SetSolution {
        x: z,
        multipliers,
        steps: 0,
        residual,
        timed_out: false,
    }
}

/// Refines `solution` for the set `active` (at most `max_steps` steps, none after
/// `deadline`) until its scaled residual is at most `target` or stops decreasing, keeping the
/// best iterate.
pub fn refine(
    problem: &QpProblem,
    scales: &ResidualScales,
    active: &[bool],
    solver: &mut SetSolver<'_>,
    solution: &mut SetSolution,
    limits: &Limits,
) {
    let Limits {
        max_steps,
        target,
        deadline,
    } = *limits;
    let n = problem.dofs();
    let mut z: Vec<f64> = solution
        .x
        .iter()
        .chain(&solution.multipliers)
        .copied()
        .collect();
    let (mut r, mut norm) = residual(problem, scales, active, &z);
    let mut steps = 0;
    while steps < max_steps && norm > target.max(ROUND_OFF) && norm.is_finite() {
        if deadline.is_some_and(|d| Instant::now() >= d) {
            solution.timed_out = true;
            break;
        }
        solver.solve_in_place(&mut r);
        clear_inactive(&mut r[n..], active);
        let candidate: Vec<f64> = z.iter().zip(&r).map(|(a, b)| a + b).collect();
        let (next_r, next_norm) = residual(problem, scales, active, &candidate);
        steps += 1;
        if next_norm.is_nan() || next_norm >= norm {
            break;
        }
        let progress = next_norm < PROGRESS * norm;
        z = candidate;
        r = next_r;
        norm = next_norm;
        if !progress {
            break;
        }
    }
    solution.multipliers = z.split_off(n);
    solution.x = z;
    solution.steps += steps;
    solution.residual = norm;
}

fn clear_inactive(multipliers: &mut [f64], active: &[bool]) {
    multipliers
        .iter_mut()
        .zip(active)
        .filter(|(_, &on)| !on)
        .for_each(|(l, _)| *l = 0.0);
}

/// The unregularised KKT residual [r_x; r_λ] of z = [x; λ] and its scaled size.
fn residual(
    problem: &QpProblem,
    scales: &ResidualScales,
    active: &[bool],
    z: &[f64],
) -> (Vec<f64>, f64) {
    let n = problem.dofs();
    let (x, multipliers) = z.split_at(n);
    let ax = mat_vec(&problem.stiffness, x);
    let btl = mat_t_vec(&problem.constraints, multipliers);
    let bx = mat_vec(&problem.constraints, x);
    let mut r = Vec::with_capacity(z.len());
    let mut norm = 0.0_f64;
    for ((f, a), b) in problem.load.iter().zip(&ax).zip(&btl) {
        let v = f - a - b;
        norm = norm.max(v.abs() / scales.force);
        r.push(v);
    }
    for (((g, b), &on), xi) in problem.gap.iter().zip(&bx).zip(active).zip(&scales.rows) {
        let v = if on { g - b } else { 0.0 };
        norm = norm.max(v.abs() / xi.max(f64::MIN_POSITIVE));
        r.push(v);
    }
    if !norm.is_finite() {
        norm = f64::INFINITY;
    }
    (r, norm)
}
