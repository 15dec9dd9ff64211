//! Coulomb friction (docs/scene.md, "Friction"): a backend's own method for the coupled
//! conditions ([`QpBackend::solve_coulomb`], pdas's semismooth Newton) or the fixed point over
//! Tresca problems through any backend, as [`SolveOptions::coulomb`] chooses
//! ([`CoulombMethod::Auto`]: the backend's own method when it has one).  Both answers are judged
//! the same way: by the residuals with each Coulomb row bounded by μ max(0, λₙ) of the answer.
//!
//! # The fixed point
//!
//! Coulomb's bound μ λₙ depends on the normal multiplier, so the contact problem is no longer a
//! QP.  Each outer iteration k solves the Tresca QP whose Coulomb rows have the bounds
//! sᵏ = μ max(0, λₙᵏ⁻¹) of the previous iterate, through any backend that solves box rows, and
//! stops when the answer meets the tolerance *with its own bounds* μ max(0, λₙᵏ): then it
//! satisfies Coulomb's conditions, measured by the same residuals as every answer.  The first
//! iterate has every Coulomb row bounded by the whole load ‖f‖₁ (in the scaled problem's force
//! unit, at least 1): nearly every node sticks, so a body that only friction holds sideways is
//! held from the start (a frictionless start would let it slide away, an unbounded problem).
//!
//! The map λₙᵏ⁻¹ ↦ λₙᵏ contracts for small μ (the coupling of normal and tangential forces is
//! of order μ), so the iterates converge linearly; [`CoulombRun`] reports the outer iterations
//! and the last ratio of successive changes.  When that ratio shows no contraction the inner
//! answers' own inaccuracy is moving the bounds, and the next inner solves are asked for a
//! tighter tolerance (see [`inner_tolerance`]).  A run that has not converged after [`MAX_OUTER`]
//! iterations ends `max-iterations`; one whose inner solve fails ends with that solve's status;
//! one whose bounds reproduce themselves exactly while the answer misses the tolerance ends
//! `inaccurate` at once (the next solve would repeat this one).

use std::time::{Duration, Instant};

use serde::Serialize;

use super::{finish, ScaledQp, Solution, SolveError};
use crate::model::Model;
use crate::qp::{
    checked_status, CoulombLink, CoulombMethod, CoulombRows, QpBackend, QpError, QpProblem,
    QpStatus, ResidualScales, SolveOptions,
};
use crate::scene::Friction;

/// The outer iterations allowed (each is one full solve).
pub const MAX_OUTER: usize = 100;

/// How Coulomb's conditions were solved.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct CoulombRun {
    /// `fixed-point` or `newton` (the backend's own method).
    pub method: CoulombMethod,
    /// Outer iterations: Tresca solves of the fixed point; 1 for the backend's own method.
    pub outer_iterations: usize,
    /// The fixed point's last change of the Coulomb bounds, max |sᵏ⁺¹ − sᵏ| / max sᵏ⁺¹
    /// (absent for the backend's own method).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub last_change: Option<f64>,
    /// The ratio of the last two changes (an estimate of the map's contraction; `None` before
    /// two changes were measured, and then absent from result.json).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contraction: Option<f64>,
    /// Whether the answer met the tolerance with its own bounds.
    pub converged: bool,
}

/// The Coulomb rows of `model` in its QP `problem` (the box block follows the normal rows).
fn coulomb_rows(model: &Model, problem: &QpProblem) -> Result<CoulombRows, QpError> {
    let first = model.normal_rows();
    let links = model
        .tangential
        .iter()
        .enumerate()
        .filter_map(|(slot, t)| match t.law {
            Friction::Coulomb(mu) => Some(CoulombLink {
                row: first + slot,
                normal_row: t.normal_row,
                mu,
            }),
            Friction::Tresca(_) => None,
        })
        .collect();
    CoulombRows::new(problem, links)
}

/// Solves the Coulomb problem of `model` by the method [`SolveOptions::coulomb`] chooses.
pub(super) fn solve(
    model: &Model,
    qp: &ScaledQp,
    backend: &mut dyn QpBackend,
    options: &SolveOptions,
) -> Result<Solution, SolveError> {
    let rows = coulomb_rows(model, &qp.problem)?;
    let own = match options.coulomb {
        CoulombMethod::Auto => backend.solves_coulomb(&qp.problem),
        CoulombMethod::FixedPoint => false,
        CoulombMethod::Newton => true,
    };
    if !own {
        return fixed_point(model, qp, &rows, backend, options);
    }
    let first = own_method(model, qp, &rows, backend, options);
    if options.coulomb != CoulombMethod::Auto {
        return first;
    }
    // Auto: the backend's own method first; where it does not solve (its active sets cycle, or
    // it cannot run), the fixed point — unless the time is up.
    let why = match &first {
        Ok(s) if s.status == QpStatus::Solved || s.status == QpStatus::TimeLimit => return first,
        Ok(s) => s.status.as_str().to_string(),
        Err(e) => e.to_string(),
    };
    let remaining = options
        .time_limit
        .map(|t| t.saturating_sub(first.as_ref().map_or(Duration::ZERO, |s| s.solve_time)));
    if remaining.is_some_and(|t| t.is_zero()) {
        return first;
    }
    let fallback_options = SolveOptions {
        time_limit: remaining,
        ..options.clone()
    };
    let mut solution = fixed_point(model, qp, &rows, backend, &fallback_options)?;
    let spent = first.as_ref().map_or(Duration::ZERO, |s| s.solve_time);
    solution.solve_time += spent;
    let note = format!(
        "{}'s own Coulomb method: {why}; then the fixed point",
        backend.name()
    );
    solution.message = Some(match solution.message.take() {
        Some(m) => format!("{note}: {m}"),
        None => note,
    });
    Ok(solution)
}

/// The first bounds of the Coulomb rows: the whole load ‖f‖₁ (at least 1 in the scaled units),
/// so that nearly every node sticks at first.
fn first_bounds(problem: &QpProblem, rows: &CoulombRows) -> Vec<f64> {
    let first = problem.load.iter().map(|f| f.abs()).sum::<f64>().max(1.0);
    vec![first; rows.links().len()]
}

/// The backend's own method for the coupled conditions, judged like the fixed point's answer.
fn own_method(
    model: &Model,
    qp: &ScaledQp,
    rows: &CoulombRows,
    backend: &mut dyn QpBackend,
    options: &SolveOptions,
) -> Result<Solution, SolveError> {
    let start = Instant::now();
    let mut problem = qp.problem.clone();
    let first = first_bounds(&problem, rows);
    rows.set_bounds(&mut problem, &first);
    let raw = backend.solve_coulomb(&problem, rows, options)?;
    // Judged with its own bounds μ max(0, λₙ): Coulomb's conditions exactly.
    rows.set_bounds(&mut problem, &rows.bounds(&raw.multipliers));
    let mut solution = finish(
        model,
        &problem,
        qp.scaling,
        backend.name(),
        raw,
        start.elapsed(),
        options,
    );
    solution.coulomb = Some(CoulombRun {
        method: CoulombMethod::Newton,
        outer_iterations: 1,
        last_change: None,
        contraction: None,
        converged: solution.status == QpStatus::Solved,
    });
    Ok(solution)
}

/// Successive changes of the bounds that no longer fall below this fraction of the one before
/// mean the fixed point has stopped contracting (measured contractions of converging runs:
/// 0.02–0.06 at μ = 0.3, SSNV128's μ = 1 about 0.3).
const STALLED_CONTRACTION: f64 = 0.9;

/// The inner solves' tolerance never falls below the requested one by more than this factor.
const MAX_TIGHTENING: f64 = 1e-3;

/// The tolerance of the next inner (Tresca) solve: the current one, or ten times tighter when
/// the last two changes of the bounds show no contraction while the answer misses the
/// tolerance — then the inner answers' own inaccuracy (an interior-point method's noise at the
/// tolerance) moves the bounds as much as the map does, and a tighter inner solve is the only
/// way on (measured on SSNV128 through clarabel at tol 1e-9: contraction 1.07 with bounds
/// moving by 1.4e-8 per iteration, 100 outer iterations without converging).  At most
/// [`MAX_TIGHTENING`] below `requested`.
fn inner_tolerance(changes: &[f64], current: f64, requested: f64) -> f64 {
    let stalled = match changes {
        [.., before, last] => *last >= STALLED_CONTRACTION * before,
        _ => false,
    };
    if stalled {
        (0.1 * current).max(MAX_TIGHTENING * requested)
    } else {
        current
    }
}

/// The fixed point (see the module docs) on the scaled QP `qp` of `model`.
fn fixed_point(
    model: &Model,
    qp: &ScaledQp,
    rows: &CoulombRows,
    backend: &mut dyn QpBackend,
    options: &SolveOptions,
) -> Result<Solution, SolveError> {
    let start = Instant::now();
    let mut problem = qp.problem.clone();
    let scales = ResidualScales::of(&problem);
    let mut bounds = first_bounds(&problem, rows);
    rows.set_bounds(&mut problem, &bounds);
    let mut iterations = 0;
    let mut changes: Vec<f64> = Vec::new();
    let mut outer = 0;
    let mut inner = options.clone();
    let (raw, converged) = loop {
        outer += 1;
        let mut raw = backend.solve(&problem, &inner)?;
        iterations += raw.iterations;
        let next = rows.bounds(&raw.multipliers);
        let scale = next.iter().fold(0.0_f64, |m, s| m.max(*s));
        // Relative to the larger of the two sets of bounds: a solve whose normal forces all
        // vanish (a failed inner solve answers zeros) changes them by 100 %, not by 1e306.
        let before = bounds.iter().fold(0.0_f64, |m, s| m.max(*s));
        let change = bounds
            .iter()
            .zip(&next)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0_f64, f64::max)
            / scale.max(before).max(f64::MIN_POSITIVE);
        changes.push(change);
        // Judged with its own bounds μ max(0, λₙ): Coulomb's conditions exactly.
        rows.set_bounds(&mut problem, &next);
        // An inaccurate inner answer may still meet the tolerance once judged with the next
        // bounds, or lead to one that does; any other verdict ends the fixed point.
        if !matches!(raw.status, QpStatus::Solved | QpStatus::Inaccurate) {
            break (raw, false);
        }
        let residuals = rows.residuals(&problem, &scales, &raw.x, &raw.multipliers);
        if checked_status(raw.status, &residuals, options.tol) == QpStatus::Solved {
            break (raw, true);
        }
        if change == 0.0 {
            // The bounds reproduce themselves: the next solve would be this one again, and its
            // answer misses the tolerance — the inner solve's inaccuracy, not the fixed point's.
            raw.status = QpStatus::Inaccurate;
            break (raw, false);
        }
        if outer >= MAX_OUTER || options.time_limit.is_some_and(|t| start.elapsed() >= t) {
            raw.status = if outer >= MAX_OUTER {
                QpStatus::MaxIterations
            } else {
                QpStatus::TimeLimit
            };
            break (raw, false);
        }
        // The next solve drops the bounds of normal forces at round-off level (at most tol of
        // the largest: an interior-point method leaves 1e-10 on open rows), which would give
        // nearly free tangential rows; the check above keeps the exact bounds.
        bounds = next
            .iter()
            .map(|&s| if s > options.tol * scale { s } else { 0.0 })
            .collect();
        rows.set_bounds(&mut problem, &bounds);
        inner.tol = inner_tolerance(&changes, inner.tol, options.tol);
    };
    let run = CoulombRun {
        method: CoulombMethod::FixedPoint,
        outer_iterations: outer,
        last_change: Some(changes.last().copied().unwrap_or(0.0)),
        contraction: (changes.len() >= 2)
            .then(|| changes[changes.len() - 1] / changes[changes.len() - 2]),
        converged,
    };
    let mut raw = raw;
    raw.iterations = iterations;
    let note = format!(
        "Coulomb fixed point: {} outer iteration(s){}, last change of the bounds {:.2e}{}",
        run.outer_iterations,
        if converged {
            ", converged"
        } else {
            ", not converged"
        },
        run.last_change.unwrap_or(0.0),
        run.contraction
            .map(|c| format!(", contraction {c:.3e}"))
            .unwrap_or_default()
    );
    raw.message = Some(match raw.message.take() {
        Some(m) => format!("{note}; last solve: {m}"),
        None => note,
    });
    let mut solution = finish(
        model,
        &problem,
        qp.scaling,
        backend.name(),
        raw,
        start.elapsed(),
        options,
    );
    solution.coulomb = Some(run);
    Ok(solution)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_inner_tolerance_tightens_only_when_the_changes_stop_falling() {
        // Contracting (ratio 0.05, the strips' measured rate): unchanged.
        assert_eq!(inner_tolerance(&[1e-2, 5e-4], 1e-8, 1e-8), 1e-8);
        // One change only: no ratio yet.
        assert_eq!(inner_tolerance(&[1e-9], 1e-8, 1e-8), 1e-8);
        // Stalled (SSNV128 through clarabel: ratio 1.07): ten times tighter ...
        let tighter = inner_tolerance(&[1.3e-8, 1.4e-8], 1e-9, 1e-9);
        assert!((tighter / 1e-10 - 1.0).abs() < 1e-12, "{tighter:e}");
        // ... but never below 1e-3 of the requested tolerance.
        let floor = inner_tolerance(&[1e-8, 1e-8], 1e-12, 1e-9);
        assert!((floor / 1e-12 - 1.0).abs() < 1e-12, "{floor:e}");
    }
}
