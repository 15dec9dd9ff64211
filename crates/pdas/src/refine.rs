//! One solve of the equality-constrained QP on an active set F, made accurate by iterative
//! refinement against the unregularised KKT system:
//!
//! ```text
//! r_x = f − A x − Bᵀ λ,   r_λ = g_F − B_F x,   (λᵢ fixed off F: 0, or ±sᵢ on a slipping box row)
//! [Δx; Δλ] = K⁻¹ [r_x; r_λ],  x += Δx,  λ_F += Δλ_F
//! ```
//!
//! with the products taken with the sparse A and B themselves, not with the regularised K.
//! The regularisations δ, ρ and the round-off of the factor only slow the iteration down; it
//! stops when the scaled residual stops decreasing (or is at round-off level), keeping the
//! best iterate.

use std::time::Instant;

use signorini_qp::{CscMatrix, QpProblem, ResidualScales};

use crate::update::SetSolver;

/// Refinement stops once the residual is within this multiple of the round-off in forming it.
const ROUND_OFF_MULTIPLE: f64 = 4.0;

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
    /// The final scaled residual max(‖r_x‖∞ / F, maxᵢ |r_λ,ᵢ| / Xᵢ) (NaN until refined).
    pub residual: f64,
    /// True when a time limit interrupted the refinement.
    pub timed_out: bool,
    /// The multiplier part of the last refinement correction, accepted or not (empty before
    /// one).  On a set whose rows cannot all hold (B_Fᵀy = 0, g_Fᵀy < 0 for some y ≥ 0) the
    /// regularised solve leaves g_F − B_F x = δλ, and the correction solves
    /// (H + δI) Δλ = δλ: the ray's part of λ comes back whole, the rest shrinks by about δ/σ
    /// (σ the smallest nonzero eigenvalue of H = B_F A⁻¹ B_Fᵀ) — a far cleaner ray than λ.
    pub correction: Vec<f64>,
}

impl SetSolution {
    /// Whether x and λ are finite.
    pub fn is_finite(&self) -> bool {
        self.x
            .iter()
            .chain(&self.multipliers)
            .all(|v| v.is_finite())
    }
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

/// The right-hand side of a set's first solve, [f − B_Iᵀ λ_I; g_F]: λ_I the fixed multipliers
/// of the inactive rows (`fixed`: 0 on a one-sided row, ±s on a slipping box row; `None`: all
/// 0), which K's zeroed rows leave to the right-hand side.
pub fn first_rhs(problem: &QpProblem, active: &[bool], fixed: Option<&[f64]>) -> Vec<f64> {
    let known = fixed.map(|l| signorini_qp::mat_t_vec(&problem.constraints, l));
    problem
        .load
        .iter()
        .enumerate()
        .map(|(j, f)| known.as_ref().map_or(*f, |k| f - k[j]))
        .chain(
            problem
                .gap
                .iter()
                .zip(active)
                .map(|(g, &on)| if on { *g } else { 0.0 }),
        )
        .collect()
}

/// Solves K z = [`first_rhs`] with the current factor, without refinement.
pub fn first_solve(
    problem: &QpProblem,
    active: &[bool],
    fixed: Option<&[f64]>,
    solver: &mut SetSolver<'_>,
) -> SetSolution {
    let mut z = first_rhs(problem, active, fixed);
    solver.solve_in_place(&mut z);
    first_solution(problem, active, fixed, solver, z)
}

/// The set's solution from z = K⁻¹ [`first_rhs`] (solved by [`first_solve`], or in one batch
/// with an update's columns): the inactive rows' multipliers set to their fixed values.
pub fn first_solution(
    problem: &QpProblem,
    active: &[bool],
    fixed: Option<&[f64]>,
    solver: &SetSolver<'_>,
    mut z: Vec<f64>,
) -> SetSolution {
    let n = problem.dofs();
    clear_inactive(&mut z[n..], active);
    if let Some(fixed) = fixed {
        for ((l, &on), v) in z[n..].iter_mut().zip(active).zip(fixed) {
            if !on {
                *l = *v;
            }
        }
    }
    let mut multipliers = z.split_off(n);
    solver.fill(&mut multipliers);
    SetSolution {
        x: z,
        multipliers,
        steps: 0,
        // Measured by `refine` when the set is kept; an iterate about to be left is not.
        residual: f64::NAN,
        timed_out: false,
        correction: Vec::new(),
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
    let first = residual(problem, scales, active, &z);
    let (mut r, mut norm) = (first.vector, first.norm);
    // Refinement cannot beat the round-off of its own residual: stop within a small multiple.
    let floor = ROUND_OFF_MULTIPLE * first.round_off;
    let mut steps = 0;
    while steps < max_steps && norm > target.max(floor) && norm.is_finite() {
        if deadline.is_some_and(|d| Instant::now() >= d) {
            solution.timed_out = true;
            break;
        }
        solver.solve_in_place(&mut r);
        clear_inactive(&mut r[n..], active);
        solution.correction.clear();
        solution.correction.extend_from_slice(&r[n..]);
        let mut candidate: Vec<f64> = z.iter().zip(&r).map(|(a, b)| a + b).collect();
        solver.fill(&mut candidate[n..]);
        let next = residual(problem, scales, active, &candidate);
        let (next_r, next_norm) = (next.vector, next.norm);
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

/// The unregularised KKT residual of z = [x; λ] and its size.
struct Residual {
    /// [r_x; r_λ].
    vector: Vec<f64>,
    /// max(‖r_x‖∞ / F, maxᵢ |r_λ,ᵢ| / Xᵢ).
    norm: f64,
    /// The same measure of the round-off in forming it, ε (|A||x| + |B|ᵀ|λ| + |f|) and
    /// ε (|B||x| + |g|): no refinement can go much below it.
    round_off: f64,
}

/// y += M v and |y| += |M| |v| for a CSC matrix, in one pass.
fn mat_vec_abs(m: &CscMatrix, v: &[f64], y: &mut [f64], y_abs: &mut [f64]) {
    for (j, col) in m.outer_iterator().enumerate() {
        let vj = v[j];
        if vj != 0.0 {
            for (i, a) in col.iter() {
                y[i] += a * vj;
                y_abs[i] += (a * vj).abs();
            }
        }
    }
}

/// y += Mᵀ v and |y| += |M|ᵀ |v| for a CSC matrix, in one pass.
fn mat_t_vec_abs(m: &CscMatrix, v: &[f64], y: &mut [f64], y_abs: &mut [f64]) {
    for ((col, yj), yj_abs) in m.outer_iterator().zip(y.iter_mut()).zip(y_abs.iter_mut()) {
        for (i, a) in col.iter() {
            *yj += a * v[i];
            *yj_abs += (a * v[i]).abs();
        }
    }
}

fn residual(problem: &QpProblem, scales: &ResidualScales, active: &[bool], z: &[f64]) -> Residual {
    let n = problem.dofs();
    let m = problem.rows();
    let (x, multipliers) = z.split_at(n);
    let mut ax = vec![0.0; n];
    let mut ax_abs = vec![0.0; n];
    mat_vec_abs(&problem.stiffness, x, &mut ax, &mut ax_abs);
    mat_t_vec_abs(&problem.constraints, multipliers, &mut ax, &mut ax_abs);
    let mut bx = vec![0.0; m];
    let mut bx_abs = vec![0.0; m];
    mat_vec_abs(&problem.constraints, x, &mut bx, &mut bx_abs);
    let mut vector = Vec::with_capacity(z.len());
    let mut norm = 0.0_f64;
    let mut round_off = 0.0_f64;
    // Each DOF against the force its own spring gives over its component's length (the scale
    // its equilibrium is judged by, not the whole problem's: a very soft body beside a stiff
    // one was left unrefined at 1e-9 of the stiff one's forces, issue 41).
    for (((f, a), a_abs), &scale) in problem
        .load
        .iter()
        .zip(&ax)
        .zip(&ax_abs)
        .zip(&scales.dof_reach)
    {
        let v = f - a;
        norm = norm.max(v.abs() / scale);
        round_off = round_off.max((a_abs + f.abs()) / scale);
        vector.push(v);
    }
    for ((((g, b), b_abs), &on), xi) in problem
        .gap
        .iter()
        .zip(&bx)
        .zip(&bx_abs)
        .zip(active)
        .zip(&scales.rows)
    {
        let scale = xi.max(f64::MIN_POSITIVE);
        let v = if on { g - b } else { 0.0 };
        norm = norm.max(v.abs() / scale);
        if on {
            round_off = round_off.max((b_abs + g.abs()) / scale);
        }
        vector.push(v);
    }
    if !norm.is_finite() {
        norm = f64::INFINITY;
    }
    Residual {
        vector,
        norm,
        round_off: f64::EPSILON * round_off,
    }
}
