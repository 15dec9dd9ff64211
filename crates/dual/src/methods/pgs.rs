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

use signorini_qp::{dot, mat_t_vec, QpError, QpStatus};

use super::intervals;

use crate::dual::{DualData, Outcome};
use crate::error::DualError;
use crate::hessian::{dual_hessian, DenseSym};
use crate::monitor::{finish_at_limit, Monitor, Next};
use crate::settings::DualSettings;

/// Relative rise (× the objective's scale) of the dense dual objective over one sweep that
/// counts as a loss of monotonicity rather than round-off.
const SWEEP_RISE: f64 = 1e-12;

/// Relative rise of the dual objective measured with the sparse solve between two full checks
/// that proves the dense H inconsistent with A and B.  Looser than [`SWEEP_RISE`]: that value
/// carries the forward error of a sparse solve.
const CHECK_RISE: f64 = 1e-9;

/// Relative difference (× the scale of the terms) between the dual objective from the dense H
/// and the one measured with the sparse solve, at the same λ, above which the dense H is
/// inconsistent with A and B.  The two differ by the error of forming H (~ε cond(A)); 1e-6 leaves
/// room for condition numbers up to ~1e10.
const CONSISTENCY: f64 = 1e-6;

/// Sweeps in a row whose decrease of the dual objective stays below round-off (relative
/// [`STALL_DECREASE`]) before PGS gives up as stalled.
const STALL_SWEEPS: usize = 2000;

/// Decrease (relative to the objective's scale) below which a sweep made no progress.
const STALL_DECREASE: f64 = 1e-15;

/// Runs projected Gauss–Seidel until the monitor stops it.
pub fn solve(
    data: &mut DualData<'_>,
    settings: &DualSettings,
    monitor: &mut Monitor<'_>,
) -> Result<Outcome, DualError> {
    // H that does not fit is a resource refusal (exit 3), like any other memory refusal: the
    // scene is fine, this machine cannot hold what projected Gauss–Seidel sweeps.
    let hessian = dual_hessian(data, settings, 0.0, &|| monitor.out_of_time()).map_err(|e| {
        match e {
            DualError::Refused(QpError::TooLarge {
                backend,
                what,
                needed,
                available,
            }) => DualError::Refused(QpError::TooLarge {
                backend,
                what: format!(
                    "{what} (projected Gauss–Seidel sweeps its columns; dual-ssn, pdas and dual-uzawa run without it)"
                ),
                needed,
                available,
            }),
            other => other,
        }
    })?;
    Ok(run(data, settings, monitor, hessian))
}

/// ½ λᵀ H λ − dᵀ λ = ½ λᵀ (w − d) from the maintained gradient w = H λ − d, with its scale
/// ½ |λ|ᵀ(|w| + |d|) (the size of the terms that cancel).
fn dense_objective(lambda: &[f64], gradient: &[f64], load: &[f64]) -> (f64, f64) {
    lambda
        .iter()
        .zip(gradient)
        .zip(load)
        .fold((0.0, 0.0), |(v, s), ((l, w), d)| {
            (
                v + 0.5 * l * (w - d),
                s + 0.5 * l.abs() * (w.abs() + d.abs()),
            )
        })
}

/// The same objective without the dense H, from u = A⁺(f − Bᵀλ): with Bᵀλ = f − A u,
/// λᵀHλ = (Bᵀλ)ᵀ(A⁺f − u) and dᵀλ = (Bᵀλ)ᵀA⁺f − gᵀλ, so
/// ½ λᵀHλ − dᵀλ = −½ (Bᵀλ)ᵀ(A⁺f + u) + gᵀλ; plus the augmented-Lagrangian terms
/// ½ c ‖Gλ‖² + (μ − c e)ᵀ G λ, which the dense objective includes through H + c GᵀG.
fn sparse_objective(data: &DualData<'_>, lambda: &[f64], free: &[f64]) -> (f64, f64) {
    let btl = mat_t_vec(&data.problem.constraints, lambda);
    let (mut value, mut scale) =
        btl.iter()
            .zip(data.base())
            .zip(free)
            .fold((0.0, 0.0), |(v, s), ((b, a), u)| {
                (
                    v - 0.5 * b * (a + u),
                    s + 0.5 * b.abs() * (a.abs() + u.abs()),
                )
            });
    for (g, l) in data.problem.gap.iter().zip(lambda) {
        value += g * l;
        scale += (g * l).abs();
    }
    if data.floating() {
        let c = data.penalty;
        for ((row, e), mu) in data
            .modes
            .coupling
            .iter()
            .zip(&data.modes.load)
            .zip(&data.multiplier)
        {
            let gl = dot(row, lambda);
            value += 0.5 * c * gl * gl + (mu - c * e) * gl;
            scale += 0.5 * c * gl * gl + (mu.abs() + c * e.abs()) * gl.abs();
        }
    }
    (value, scale)
}

/// Runs projected Gauss–Seidel on a given H (H = B A⁺ Bᵀ, before the penalty).  Stops with
/// `numerical-error` when a sweep raises the dual objective beyond round-off, or when the
/// objective measured with the sparse solve rises between checks (the dense H is inconsistent
/// with A and B: formed inaccurately, or not positive semidefinite); with `inaccurate` when it
/// stalls for [`STALL_SWEEPS`] sweeps.
pub fn run(
    data: &mut DualData<'_>,
    settings: &DualSettings,
    monitor: &mut Monitor<'_>,
    mut hessian: DenseSym,
) -> Outcome {
    if data.floating() {
        let norm = hessian.largest_eigenvalue(settings.power_iterations);
        data.set_penalty(norm, settings.equality_penalty);
        hessian.add_penalty(&data.modes, data.penalty);
    }
    let mut pgs = Pgs::start(data, settings, hessian);
    monitor.calibrate(data.base());
    loop {
        if let Some((status, message)) = monitor.limit(pgs.iter) {
            let lambda = std::mem::take(&mut pgs.lambda);
            return finish_at_limit(data, monitor, pgs.iter, lambda, status, message);
        }
        if let Some(outcome) = pgs.sweep(data) {
            return outcome;
        }
        let estimate = monitor.estimate(&pgs.lambda, &pgs.gradient);
        if !monitor.due(pgs.iter, estimate) && pgs.stalled < STALL_SWEEPS {
            continue;
        }
        if let Some(outcome) = pgs.full_check(data, monitor) {
            return outcome;
        }
    }
}

/// The state of projected Gauss–Seidel between sweeps.
struct Pgs {
    /// H (+ c GᵀG for a floating body).
    hessian: DenseSym,
    /// Hᵢᵢ, kept away from zero ([`safe_diagonal`]).
    diagonal: Vec<f64>,
    /// ω.
    relaxation: f64,
    /// d, the dual load.
    dual_load: Vec<f64>,
    /// The load of the inner problem (d with the augmented-Lagrangian terms).
    inner_load: Vec<f64>,
    /// Each multiplier's interval [lo, hi]: [0, ∞) for a contact row, [−s, s] for a box row.
    bounds: Vec<(f64, f64)>,
    /// λ.
    lambda: Vec<f64>,
    /// w = H λ − d, kept in step by the sweeps.
    gradient: Vec<f64>,
    /// Sweeps so far.
    iter: usize,
    /// Time spent sweeping.
    sweep_time: Duration,
    /// The dense dual objective after the last sweep.
    objective: f64,
    /// The sparse dual objective at the last full check, if one was made since the last
    /// multiplier update.
    checked: Option<f64>,
    /// Sweeps in a row without a decrease beyond round-off.
    stalled: usize,
    /// The best KKT residuals at the full checks.
    progress: Progress,
}

impl Pgs {
    /// λ = 0 and its gradient.
    fn start(data: &DualData<'_>, settings: &DualSettings, hessian: DenseSym) -> Self {
        let dual_load = data.dual_load();
        let inner_load = data.inner_load(&dual_load);
        let diagonal = safe_diagonal(&hessian);
        let lambda = vec![0.0; data.rows()];
        let bounds = intervals::of(data.problem);
        let gradient = residual(&hessian, &lambda, &inner_load);
        let objective = dense_objective(&lambda, &gradient, &inner_load).0;
        Self {
            hessian,
            diagonal,
            relaxation: settings.relaxation,
            dual_load,
            inner_load,
            bounds,
            lambda,
            gradient,
            iter: 0,
            sweep_time: Duration::ZERO,
            objective,
            checked: None,
            stalled: 0,
            progress: Progress::default(),
        }
    }

    /// The answer (λ, `x`) with `status` at the current sweep.
    fn stop(&mut self, x: Vec<f64>, status: QpStatus, message: String) -> Outcome {
        Outcome {
            x,
            multipliers: std::mem::take(&mut self.lambda),
            status,
            iterations: self.iter,
            message,
        }
    }

    /// One sweep, then its check of monotonicity (the answer when it fails) and the count of
    /// sweeps without progress.
    fn sweep(&mut self, data: &DualData<'_>) -> Option<Outcome> {
        let started = Instant::now();
        sweep(
            &self.hessian,
            &self.diagonal,
            self.relaxation,
            &self.bounds,
            &mut self.lambda,
            &mut self.gradient,
        );
        self.sweep_time += started.elapsed();
        self.iter += 1;
        let iter = self.iter;
        let (next, scale) = dense_objective(&self.lambda, &self.gradient, &self.inner_load);
        let objective = self.objective;
        if next - objective > SWEEP_RISE * scale.max(objective.abs()) || !next.is_finite() {
            let x = data.primal(&self.lambda);
            return Some(self.stop(
                x,
                QpStatus::NumericalError,
                format!(
                    "PGS lost monotonicity: dual objective rose by {:.3e} (scale {scale:.3e}) at sweep {iter}; the dense H is not positive semidefinite (formed inaccurately?) — try dual-ssn, pdas or dual-uzawa",
                    next - objective
                ),
            ));
        }
        if objective - next <= STALL_DECREASE * scale {
            self.stalled += 1;
        } else {
            self.stalled = 0;
        }
        self.objective = next;
        None
    }

    /// The full check (one sparse solve): the monitor's verdict, the consistency of the dense
    /// H with the sparse solve, and the rate of progress; the answer when one of them stops.
    fn full_check(
        &mut self,
        data: &mut DualData<'_>,
        monitor: &mut Monitor<'_>,
    ) -> Option<Outcome> {
        let (x, sparse, sparse_scale) = self.sparse_measure(data, monitor);
        match monitor.check(data, self.iter, &self.lambda, &x) {
            Next::Continue => {}
            Next::UpdateMultiplier => {
                if let Some(message) = data.update_multiplier(&self.lambda) {
                    return Some(self.stop(x, QpStatus::DualInfeasible, message));
                }
                self.inner_load = data.inner_load(&self.dual_load);
                self.checked = None;
                self.stalled = 0;
                self.resync();
                return None;
            }
            Next::Stop(status, message) => return Some(self.stop(x, status, message)),
        }
        if let Some(message) = self.inconsistency(sparse, sparse_scale) {
            return Some(self.stop(x, QpStatus::NumericalError, message));
        }
        self.checked = Some(sparse);
        let worst = monitor.residuals(&x, &self.lambda).worst();
        if let Some(message) =
            self.progress
                .record(self.iter, worst, monitor.tol(), monitor.max_iter())
        {
            let message = monitor.explain(message);
            return Some(self.stop(x, QpStatus::Inaccurate, message));
        }
        if self.stalled >= STALL_SWEEPS {
            let message = monitor.explain(format!(
                "PGS stalled: the dual objective changed by less than round-off for {STALL_SWEEPS} sweeps (at sweep {}) without meeting the tolerance — try dual-ssn or pdas",
                self.iter
            ));
            return Some(self.stop(x, QpStatus::Inaccurate, message));
        }
        self.resync();
        None
    }

    /// x(λ) and the dual objective measured with the sparse solve (with its scale); stretches
    /// the monitor's check period so that the checks (one solve each) stay under ~10 % of the
    /// sweeping time.
    fn sparse_measure(
        &self,
        data: &DualData<'_>,
        monitor: &mut Monitor<'_>,
    ) -> (Vec<f64>, f64, f64) {
        let started = Instant::now();
        let free = data.free_part(&self.lambda);
        let (sparse, sparse_scale) = sparse_objective(data, &self.lambda, &free);
        let x = data.primal_from(free, &self.lambda);
        let check_time = started.elapsed();
        let per_sweep = self.sweep_time.as_secs_f64() / self.iter as f64;
        if per_sweep > 0.0 {
            let period = (10.0 * check_time.as_secs_f64() / per_sweep).ceil();
            monitor.stretch_period(period.min(1e6) as usize);
        }
        (x, sparse, sparse_scale)
    }

    /// Why the dense H is inconsistent with A and B, if it is: the dense and the sparse
    /// objective differ at the same λ, or the sparse one rose since the last check.
    fn inconsistency(&self, sparse: f64, sparse_scale: f64) -> Option<String> {
        let iter = self.iter;
        let (dense, _) = dense_objective(&self.lambda, &self.gradient, &self.inner_load);
        if (dense - sparse).abs() > CONSISTENCY * sparse_scale || !dense.is_finite() {
            return Some(format!(
                "PGS lost monotonicity: at sweep {iter} the dual objective is {dense:.6e} with the dense H but {sparse:.6e} measured with the sparse solve (scale {sparse_scale:.1e}): the dense H is inconsistent with A and B (ill-conditioned dual, or H not positive semidefinite) — try dual-ssn, pdas or dual-uzawa"
            ));
        }
        let previous = self.checked?;
        (sparse - previous > CHECK_RISE * sparse_scale.max(previous.abs())).then(|| {
            format!(
                "PGS lost monotonicity: dual objective (measured with the sparse solve) rose by {:.3e} (scale {sparse_scale:.3e}) by sweep {iter} while the dense one fell: the dense H is inconsistent with A and B (ill-conditioned dual) — try dual-ssn, pdas or dual-uzawa",
                sparse - previous
            )
        })
    }

    /// Recomputes w = H λ − d and the dense objective from scratch (after a check, or a new
    /// load), so that the sweeps' round-off does not accumulate.
    fn resync(&mut self) {
        self.gradient = residual(&self.hessian, &self.lambda, &self.inner_load);
        self.objective = dense_objective(&self.lambda, &self.gradient, &self.inner_load).0;
    }
}

/// Sweeps before the rate of progress is judged at all.
const PROGRESS_MIN_SWEEPS: usize = 4000;

/// The best KKT residual at each full check, to extrapolate how many sweeps the tolerance
/// would take: from the best residual at about half the sweeps so far to the best now, the
/// residual fell by a factor q over s sweeps, so reaching the tolerance needs
/// s · ln(best / tol) / ln q more.  When that exceeds the iteration limit (or nothing improved in
/// the second half), PGS says so instead of running on: a very ill-conditioned dual (a long thin
/// body) makes its convergence linear with a rate near 1.
#[derive(Debug, Default)]
struct Progress {
    /// (sweep, best residual so far) at each check.
    history: Vec<(usize, f64)>,
}

impl Progress {
    fn record(&mut self, iter: usize, worst: f64, tol: f64, max_iter: usize) -> Option<String> {
        let best = self.history.last().map_or(worst, |&(_, b)| b.min(worst));
        self.history.push((iter, best));
        if iter < PROGRESS_MIN_SWEEPS || !best.is_finite() || best <= tol {
            return None;
        }
        let &(then, earlier) = self.history.iter().find(|(i, _)| 2 * i >= iter)?;
        if then >= iter {
            return None;
        }
        let factor = earlier / best;
        let needed = if factor > 1.0 {
            (iter - then) as f64 * (best / tol).ln() / factor.ln()
        } else {
            f64::INFINITY
        };
        (iter as f64 + needed > max_iter as f64).then(|| {
            format!(
                "PGS converges too slowly: KKT residual {best:.1e} after {iter} sweeps, down only {factor:.2}× since sweep {then}; the tolerance would take ~{needed:.1e} more sweeps (limit {max_iter}) — the dual is very ill-conditioned (a long thin body?): use dual-ssn or pdas"
            )
        })
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

/// One forward sweep, each update projected onto its row's interval ([`intervals`]);
/// `gradient` = H λ − d is kept in step.
fn sweep(
    hessian: &DenseSym,
    diagonal: &[f64],
    omega: f64,
    bounds: &[(f64, f64)],
    lambda: &mut [f64],
    gradient: &mut [f64],
) {
    for i in 0..lambda.len() {
        let updated = intervals::project(lambda[i] - omega * gradient[i] / diagonal[i], bounds[i]);
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

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use std::time::Instant;

    use signorini_qp::{QpProblem, QpStatus, SolveOptions};
    use sprs::TriMat;

    use super::run;
    use crate::dual::DualData;
    use crate::hessian::DenseSym;
    use crate::monitor::Monitor;
    use crate::settings::DualSettings;

    /// A = I (2 × 2), B = I, f = (1, 1), g = (0, 0): the true H = I, d = (1, 1), λ* = (1, 1).
    fn identity_problem() -> QpProblem {
        let mut a = TriMat::new((2, 2));
        let mut b = TriMat::new((2, 2));
        for i in 0..2 {
            a.add_triplet(i, i, 1.0);
            b.add_triplet(i, i, 1.0);
        }
        QpProblem::try_new(a.to_csc(), vec![1.0, 1.0], b.to_csc(), vec![0.0, 0.0]).unwrap()
    }

    fn run_with(h: Vec<f64>, max_iter: usize) -> crate::dual::Outcome {
        let p = identity_problem();
        let mut data = DualData::new(&p, false, "dual-pgs").unwrap();
        let settings = DualSettings::default();
        let options = SolveOptions {
            max_iter: Some(max_iter),
            ..SolveOptions::default()
        };
        let mut monitor = Monitor::new(&p, &options, &settings, Instant::now());
        let hessian = DenseSym { values: h, size: 2 };
        run(&mut data, &settings, &mut monitor, hessian)
    }

    /// The true H solves it (the control: the checks do not fire on a consistent H).
    #[test]
    fn a_consistent_hessian_solves() {
        let out = run_with(vec![1.0, 0.0, 0.0, 1.0], 1000);
        assert_eq!(out.status, QpStatus::Solved, "{}", out.message);
        assert!((out.multipliers[0] - 1.0).abs() < 1e-9);
    }

    /// An H that is not positive semidefinite (as an inaccurately formed H of an ill-conditioned
    /// dual can be): [[1, −2], [−2, 1]] has the eigenvalue −1 along (1, 1) ≥ 0, so PGS on it
    /// runs off to infinity, its dense objective falling without bound while the true one (with
    /// H = I) rises.  Before the monotonicity checks it ran to the iteration limit (or produced
    /// non-finite numbers); now it stops at the first full check with the reason.
    #[test]
    fn an_indefinite_hessian_is_caught_not_run_to_the_limit() {
        let out = run_with(vec![1.0, -2.0, -2.0, 1.0], 100_000);
        assert_eq!(out.status, QpStatus::NumericalError, "{}", out.message);
        assert!(out.message.contains("lost monotonicity"), "{}", out.message);
        assert!(out.iterations < 100, "{} sweeps", out.iterations);
    }

    /// With ω ∈ (0, 2) and Hᵢᵢ > 0 every coordinate step lowers ½λᵀHλ − dᵀλ exactly, so a rise
    /// within a sweep means H is not the symmetric matrix the objective assumes: here an H
    /// formed without symmetrising, with columns (1, −1.5) and (1.5, 1).  Sweep 1 takes λ from
    /// 0 to (1, 2.5) and the objective ½λᵀ(w − d) from 0 to +0.125 (hand-computed).
    #[test]
    fn a_sweep_that_raises_the_dense_objective_is_caught() {
        let out = run_with(vec![1.0, -1.5, 1.5, 1.0], 100_000);
        assert_eq!(out.iterations, 1);
        assert_eq!(out.status, QpStatus::NumericalError, "{}", out.message);
        assert!(out.message.contains("rose by"), "{}", out.message);
    }
}
