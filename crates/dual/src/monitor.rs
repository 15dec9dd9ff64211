//! When to stop: the core's KKT residuals decide, checked every `check_every` iterations (or
//! earlier when a cheap estimate from the dual gradient says so); iteration and time limits;
//! `primal-infeasible` only from a Farkas certificate ([`FarkasRay`]) in the growth of λ.

use std::sync::Arc;
use std::time::{Duration, Instant};

use signorini_qp::{
    kkt_residuals_with, mat_t_vec, norm_inf, row_sets, FarkasRay, KktResiduals, QpProblem,
    QpStatus, ResidualScales, RowSet, SolveOptions,
};

use crate::dual::{DualData, Outcome};
use crate::settings::DualSettings;

/// What the method should do after a check.
#[derive(Debug, Clone, PartialEq)]
pub enum Next {
    /// Keep iterating.
    Continue,
    /// The inner (bound-constrained) problem is solved well enough: update μ.
    UpdateMultiplier,
    /// Stop with this verdict and message.
    Stop(QpStatus, String),
}

/// Stopping logic shared by the methods.
#[derive(Debug)]
pub struct Monitor<'a> {
    problem: &'a QpProblem,
    tol: f64,
    start: Instant,
    time_limit: Option<Duration>,
    max_iter: usize,
    check_every: usize,
    last_check: usize,
    /// An early check (estimate ≤ tol) is allowed only below this estimate: halved after an
    /// early check that failed, reset after a multiplier update.
    early_floor: f64,
    pending_estimate: f64,
    last_multipliers: Vec<f64>,
    /// Each row's bound when it is a box row (Tresca's tangential rows), `None` for a
    /// one-sided contact row.
    boxes: Vec<Option<f64>>,
    length_scale: f64,
    force_scale: f64,
    /// The fixed scales of the KKT residuals, computed once per solve.
    scales: Arc<ResidualScales>,
    /// Why the last growth of λ with gᵀδ < 0 was no certificate, for the final message.
    shortfall: Option<String>,
    /// The worst scaled KKT residual of the last full check (∞ before the first).
    last_worst: f64,
}

impl<'a> Monitor<'a> {
    /// A monitor for `problem`; the clock starts at `start`.
    pub fn new(
        problem: &'a QpProblem,
        options: &SolveOptions,
        settings: &DualSettings,
        start: Instant,
    ) -> Self {
        Self {
            problem,
            tol: options.tol,
            start,
            time_limit: options.time_limit,
            max_iter: options.max_iter.unwrap_or(settings.max_iter),
            check_every: settings.check_every,
            last_check: 0,
            early_floor: f64::INFINITY,
            pending_estimate: f64::INFINITY,
            last_multipliers: vec![0.0; problem.rows()],
            boxes: row_sets(&problem.blocks)
                .map(|set| match set {
                    RowSet::NonNegative => None,
                    RowSet::Box(bound) => Some(bound),
                })
                .collect(),
            length_scale: f64::MIN_POSITIVE,
            force_scale: norm_inf(&problem.load).max(f64::MIN_POSITIVE),
            scales: options.residual_scales(problem),
            shortfall: None,
            last_worst: f64::INFINITY,
        }
    }

    /// The core's KKT residuals of (x, λ), against the scales computed once for this solve.
    pub fn residuals(&self, x: &[f64], multipliers: &[f64]) -> KktResiduals {
        kkt_residuals_with(self.problem, &self.scales, x, multipliers)
    }

    /// `message`, followed by why the growth of λ seen last was no certificate of primal
    /// infeasibility (when one looked like it): for the message of a solve that did not
    /// converge.
    pub fn explain(&self, message: String) -> String {
        match &self.shortfall {
            Some(why) => format!("{message}; {why}"),
            None => message,
        }
    }

    /// The iteration limit in force.
    pub fn max_iter(&self) -> usize {
        self.max_iter
    }

    /// The worst scaled KKT residual of the last full check ([`Monitor::check`]), ∞ before it.
    pub fn last_worst(&self) -> f64 {
        self.last_worst
    }

    /// The requested tolerance.
    pub fn tol(&self) -> f64 {
        self.tol
    }

    /// Sets the scales of the cheap estimate from a primal point (e.g. x(0) = A⁺f).
    pub fn calibrate(&mut self, x: &[f64]) {
        self.length_scale = norm_inf(x).max(f64::MIN_POSITIVE);
    }

    /// Cheap estimate of penetration and complementarity from the dual gradient w = g − B x,
    /// with the scales of the last full check.
    pub fn estimate(&self, multipliers: &[f64], gradient: &[f64]) -> f64 {
        let mut pen = 0.0_f64;
        let mut comp = 0.0_f64;
        for ((l, w), bound) in multipliers.iter().zip(gradient).zip(&self.boxes) {
            match bound {
                // w = −(Bx − g): a box row's complementarity s|r| − λr, no penetration.
                Some(s) => comp = comp.max((s * w.abs() + l * w).abs()),
                None => {
                    pen = pen.max(-w);
                    comp = comp.max((l * w).abs());
                }
            }
        }
        (pen / self.length_scale).max(comp / (self.length_scale * self.force_scale))
    }

    /// Stretches the period of the periodic full checks to at least `period` iterations (used
    /// when an iteration is much cheaper than the solve a check needs).
    pub fn stretch_period(&mut self, period: usize) {
        self.check_every = self.check_every.max(period);
    }

    /// Is a full check due at iteration `iter`, given the cheap estimate?
    pub fn due(&mut self, iter: usize, estimate: f64) -> bool {
        self.pending_estimate = f64::INFINITY;
        if iter >= self.last_check + self.check_every {
            return true;
        }
        if estimate <= self.tol && estimate < self.early_floor {
            self.pending_estimate = estimate;
            return true;
        }
        false
    }

    /// The verdict when a limit is reached at iteration `iter`, else `None`.
    pub fn limit(&self, iter: usize) -> Option<(QpStatus, String)> {
        if iter >= self.max_iter {
            return Some((
                QpStatus::MaxIterations,
                format!("iteration limit {} reached", self.max_iter),
            ));
        }
        if let Some(limit) = self.time_limit {
            if self.start.elapsed() >= limit {
                return Some((
                    QpStatus::TimeLimit,
                    format!("time limit {limit:?} reached after {iter} iterations"),
                ));
            }
        }
        None
    }

    /// True once the time limit has passed (for loops inside one iteration: the formation of
    /// H, the refinement of a Newton step).
    pub fn out_of_time(&self) -> bool {
        self.time_limit
            .is_some_and(|limit| self.start.elapsed() >= limit)
    }

    /// Full check of (x, λ) at iteration `iter`.
    pub fn check(
        &mut self,
        data: &DualData<'_>,
        iter: usize,
        multipliers: &[f64],
        x: &[f64],
    ) -> Next {
        self.last_check = iter;
        let early = self.pending_estimate;
        if x.iter().chain(multipliers).any(|v| !v.is_finite()) {
            return Next::Stop(
                QpStatus::NumericalError,
                format!("non-finite iterate at iteration {iter}"),
            );
        }
        let r = self.residuals(x, multipliers);
        self.last_worst = r.worst();
        let btl = mat_t_vec(&self.problem.constraints, multipliers);
        self.length_scale = norm_inf(x).max(f64::MIN_POSITIVE);
        self.force_scale = norm_inf(&self.problem.load)
            .max(norm_inf(&btl))
            .max(f64::MIN_POSITIVE);
        if r.meet(self.tol) {
            return Next::Stop(
                QpStatus::Solved,
                format!("KKT residuals {:.1e} ≤ tol {:.1e}", r.worst(), self.tol),
            );
        }
        if let Some(message) = self.infeasibility(multipliers) {
            return Next::Stop(QpStatus::PrimalInfeasible, message);
        }
        self.last_multipliers.copy_from_slice(multipliers);
        let inner = r
            .relative_penetration
            .max(r.complementarity)
            .max(-r.min_multiplier);
        if data.floating() && r.stationarity > self.tol && inner <= r.stationarity {
            self.early_floor = f64::INFINITY;
            return Next::UpdateMultiplier;
        }
        if early.is_finite() {
            self.early_floor = 0.5 * early;
        }
        Next::Continue
    }

    /// A Farkas certificate in the growth of λ since the last check: δ = max(λ − λ_prev, 0),
    /// checked against B and g by [`FarkasRay`].  A growth with gᵀδ < 0 that is no
    /// certificate is remembered (see [`Monitor::explain`]) and the iteration goes on.
    fn infeasibility(&mut self, multipliers: &[f64]) -> Option<String> {
        // A box row's multiplier is bounded: it is in no ray of B x ≤ g.
        let delta: Vec<f64> = multipliers
            .iter()
            .zip(&self.last_multipliers)
            .zip(&self.boxes)
            .map(|((l, p), bound)| match bound {
                Some(_) => 0.0,
                None => (l - p).max(0.0),
            })
            .collect();
        let ray = FarkasRay::measure(self.problem, &delta)?;
        if ray.proves_infeasibility() {
            return Some(format!(
                "primal infeasible: the multipliers grow along {} (no x satisfies B x ≤ g)",
                ray.describe()
            ));
        }
        if ray.gap_fraction > 0.0 {
            self.shortfall = ray.shortfall();
        }
        None
    }
}

/// The outcome when a limit stops the method: x(λ) is formed and checked once more, so that a
/// limit reached exactly at convergence still reports `solved`.
pub fn finish_at_limit(
    data: &DualData<'_>,
    monitor: &Monitor<'_>,
    iterations: usize,
    multipliers: Vec<f64>,
    status: QpStatus,
    message: String,
) -> Outcome {
    let x = data.primal(&multipliers);
    let r = monitor.residuals(&x, &multipliers);
    let tol = monitor.tol();
    let (status, message) = if r.meet(tol) {
        (
            QpStatus::Solved,
            format!("KKT residuals {:.1e} ≤ tol {tol:.1e}", r.worst()),
        )
    } else {
        (
            status,
            monitor.explain(format!("{message}; KKT residuals {:.1e}", r.worst())),
        )
    };
    Outcome {
        x,
        multipliers,
        status,
        iterations,
        message,
    }
}
