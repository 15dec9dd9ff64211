//! Solving along a load path (`[[step]]`; docs/scene.md, "Load steps"): one solve per
//! increment, each on the QP of its own loads and prescribed values, the tangential rows'
//! slip measured from the previous increment's converged state (friction is history-dependent).
//!
//! An increment's QP shares A, B, the blocks and the scaling of the last increment's (the one
//! assembled); only f̃ = f_F − K_FD u_D and g̃ = g − B_D u_D change, computed from the model's
//! support columns and contact matrix.  A tangential row's gap is its stick value after the
//! previous increment (B_t u_prev, plus the pairing slope times the normal gap still open then:
//! `TangentialRow::stick_value`), so that its value B_t u − g_t is the slip of this increment.  The path stops at the first increment whose
//! answer is not `solved`: its status is the run's, and later increments are not run.

use std::sync::Arc;
use std::time::Duration;

use serde::Serialize;

use super::{solve_one, ScaledQp, Solution, SolveError};
use crate::model::{Increment, LoadPath, Model};
use crate::qp::{mat_vec, QpBackend, QpProblem, QpStatus, SolveOptions, WarmStart};

/// What one increment did (`result.json`'s `steps`).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct StepRecord {
    /// The step (1-based).
    pub step: usize,
    /// The increment within the step (1-based).
    pub increment: usize,
    /// Its status.
    #[schemars(with = "crate::qp::QpStatus")]
    pub status: String,
    /// Backend iterations (summed over Coulomb's outer iterations).
    pub iterations: usize,
    /// Coulomb's outer iterations, when the model has Coulomb rows.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub outer_iterations: Option<usize>,
}

/// Solves every increment of `path` in order (see the module docs); `each` sees every
/// increment's answer (prescribed values included) as soon as it is known.
pub(super) fn along(
    model: &Model,
    path: &LoadPath,
    qp: &ScaledQp,
    backend: &mut dyn QpBackend,
    options: &SolveOptions,
    each: &mut dyn FnMut(&Increment, &Solution),
) -> Result<Solution, SolveError> {
    let mut records = Vec::with_capacity(path.increments.len());
    let mut previous: Option<Vec<f64>> = None;
    let mut elapsed = Duration::ZERO;
    let mut iterations = 0;
    let count = path.increments.len();
    let mut options = options.clone();
    for (k, increment) in path.increments.iter().enumerate() {
        let prescribed = path.prescribed_at(&increment.factors);
        let step_qp = increment_qp(model, path, qp, increment, &prescribed, previous.as_deref());
        let mut solution = solve_one(model, &step_qp, backend, &options)?;
        // The next increment starts from this answer (a backend may use it: pdas's first set).
        options.warm_start = Some(Arc::new(warm_start(model, qp, &solution)));
        for (&d, &v) in model.fixed_dofs.iter().zip(&prescribed) {
            solution.displacement[d] = v;
        }
        each(increment, &solution);
        elapsed += solution.solve_time;
        iterations += solution.iterations;
        records.push(StepRecord {
            step: increment.step,
            increment: increment.increment,
            status: solution.status.as_str().to_string(),
            iterations: solution.iterations,
            outer_iterations: solution.coulomb.map(|c| c.outer_iterations),
        });
        let last = k + 1 == count;
        if last || solution.status != QpStatus::Solved {
            if !last {
                let note = format!(
                    "load path stopped at step {} increment {} of {count} increments: {}",
                    increment.step, increment.increment, solution.status
                );
                solution.message = Some(match solution.message.take() {
                    Some(m) => format!("{note}; {m}"),
                    None => note,
                });
            }
            solution.solve_time = elapsed;
            solution.iterations = iterations;
            solution.steps = records;
            solution.previous = previous;
            return Ok(solution);
        }
        previous = Some(solution.displacement);
    }
    // No increment at all cannot happen (a path has at least one step of ≥ 1 increment).
    solve_one(model, qp, backend, &options)
}

/// `solution` in the scaled QP's units: x on the free DOFs, λ per row.
fn warm_start(model: &Model, qp: &ScaledQp, solution: &Solution) -> WarmStart {
    let units = qp.scaling;
    let force = units.stiffness * units.displacement;
    WarmStart {
        x: model
            .free
            .iter()
            .map(|&d| solution.displacement[d] / units.displacement)
            .collect(),
        multipliers: solution.multipliers.iter().map(|l| l / force).collect(),
    }
}

/// The scaled QP of one increment: the last increment's with f̃ and g̃ of this one.
fn increment_qp(
    model: &Model,
    path: &LoadPath,
    qp: &ScaledQp,
    increment: &Increment,
    prescribed: &[f64],
    previous: Option<&[f64]>,
) -> ScaledQp {
    let units = qp.scaling;
    let force = units.stiffness * units.displacement;
    let (load, gap) = increment_data(
        model,
        path,
        increment,
        prescribed,
        previous,
        (units.displacement, force),
    );
    let mut problem = qp.problem.clone();
    problem.load = load;
    problem.gap = gap;
    ScaledQp {
        problem,
        scaling: units,
    }
}

/// The QP of one increment in the scene's units: `qp` (the model's QP, in the scene's units;
/// A and B are every increment's) with this increment's f̃ = f_F − K_FD u_D and g̃ = g − B_D u_D,
/// each tangential row's gap its stick value after `previous` (the full displacement of the
/// increment before; `None` for the first: the model's gap), so that the row's value B_t u − g_t
/// is this increment's slip.
/// What an increment of [`solve_scaled`](super::solve_scaled) solves, before scaling.
pub fn increment_problem(
    model: &Model,
    path: &LoadPath,
    qp: &QpProblem,
    increment: &Increment,
    previous: Option<&[f64]>,
) -> QpProblem {
    let prescribed = path.prescribed_at(&increment.factors);
    let (load, gap) = increment_data(model, path, increment, &prescribed, previous, (1.0, 1.0));
    let mut problem = qp.clone();
    problem.load = load;
    problem.gap = gap;
    problem
}

/// f̃ / force unit and g̃ / length unit of one increment (see [`increment_problem`]).
fn increment_data(
    model: &Model,
    path: &LoadPath,
    increment: &Increment,
    prescribed: &[f64],
    previous: Option<&[f64]>,
    (length, force): (f64, f64),
) -> (Vec<f64>, Vec<f64>) {
    let dofs = model.dofs.len();
    let load = path.load_at(&increment.factors);
    // K_FD u_D on every DOF (the support columns times the prescribed values).
    let lift = mat_vec(&model.supports, prescribed);
    let mut u_d = vec![0.0; dofs];
    for (&d, &v) in model.fixed_dofs.iter().zip(prescribed) {
        u_d[d] = v;
    }
    let b_d = mat_vec(&model.constraints, &u_d);
    let normal = model.normal_rows();
    let slip_from = previous.map(|u| mat_vec(&model.constraints, u));
    let gap: Vec<f64> = (0..model.rows())
        .map(|i| {
            let g = match (i.checked_sub(normal), &slip_from) {
                (Some(k), Some(bu)) => model.tangential[k].stick_value(i, &model.gap, bu),
                _ => model.gap[i],
            };
            (g - b_d[i]) / length
        })
        .collect();
    let f: Vec<f64> = model
        .free
        .iter()
        .map(|&d| (load[d] - lift[d]) / force)
        .collect();
    (f, gap)
}
