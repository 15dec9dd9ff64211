//! The primal–dual active-set iteration (Hintermüller–Ito–Kunisch):
//!
//! ```text
//! F₀ from the settings;  repeat:  solve the KKT system on F_k (refined),
//!                                 F_{k+1} = { i : λᵢ + c (Bx − g)ᵢ > 0 },
//! ```
//!
//! stopping when the set reproduces itself and (x, max(λ, 0)) meets the core's KKT residuals,
//! and honestly otherwise:
//! a set that repeats without meeting them, the iteration or time limit, or a certificate of
//! primal or dual infeasibility.  When the sets flip (a set comes back, or the changes stop
//! falling) the iteration continues with the interior-point method of [`interior`]; on a curved
//! interface it starts there ([`crate::StartSet::Auto`]).

use std::sync::Arc;
use std::time::{Duration, Instant};

use signorini_qp::{
    kkt_residuals_with, mat_vec, row_sets, CoulombRows, CscMatrix, FarkasRay, KktResiduals,
    QpProblem, QpStatus, ResidualScales, RowSet, SolveOptions,
};

use crate::coupling::Coupling;
use crate::error::PdasError;
use crate::factor::KktFactor;
use crate::kernel::{pushed_away, rigid_part};
use crate::kkt::KktMatrix;
use crate::refine::{Limits, SetSolution};
use crate::settings::{PdasSettings, StartSet};
use crate::update::ColumnCache;

mod interior;
mod plain;

/// A one-sided row is predicted active only when vᵢ = λᵢ + c (Bx − g)ᵢ exceeds this fraction
/// of the tolerance times the row's force scale: a multiplier that small changes no residual
/// by more than a thousandth of the tolerance, and round-off must not decide a row.  On a
/// long interface loaded on part of its length the first solve (every row active) leaves
/// 1 494 of 2 001 rows of `hard/strip-thin-partial` with |vᵢ| < 1e-13 F, 214 of them ≤ 0 by
/// round-off alone: counted as changes, two orderings of K gave 253 and 265 changes, and the
/// run took 4 factorisations or 3 depending on which side of the hand-over count it fell.
const NEGLIGIBLE: f64 = 1e-3;

/// Where the plain iteration handed over to the globalised one.
struct Phase1 {
    /// Iterations used so far.
    iteration: usize,
    /// The best iterate so far.
    best: Best,
}

/// Where the interior-point iteration starts.
enum InteriorStart<'a> {
    /// From the last plain step's iterate (x, λ), handed over when the plain steps flipped:
    /// s = (g − B x)⁺ + `interior::START_SHIFT` X, λ = λ⁺ + `interior::START_SHIFT` F.
    HandedOver {
        /// x of the last plain step.
        x: Vec<f64>,
        /// Its λ (not clamped).
        multipliers: &'a [f64],
    },
    /// Before any set ([`crate::StartSet::Interior`], and [`crate::StartSet::Auto`] on a
    /// curved interface): x = 0, s = g⁺ + `interior::START_SHIFT` X,
    /// λ = `interior::CENTRED_MULTIPLIER` F.
    Centred,
}

/// The best iterate so far (smallest worst KKT residual): the answer of an iteration that ends
/// without meeting the tolerance.
struct Best {
    /// The iterate.
    outcome: Outcome,
    /// Its worst scaled KKT residual (∞ before the first).
    worst: f64,
}

impl Best {
    /// Before the first iterate: x = 0, λ = 0.
    fn zero(problem: &QpProblem) -> Self {
        Self {
            outcome: Outcome {
                x: vec![0.0; problem.dofs()],
                multipliers: vec![0.0; problem.rows()],
                status: QpStatus::MaxIterations,
                iterations: 0,
                message: String::new(),
            },
            worst: f64::INFINITY,
        }
    }

    /// Keeps `candidate` when its worst residual is below the best so far.
    fn keep_if_better(&mut self, candidate: Outcome, worst: f64) {
        if worst < self.worst {
            self.worst = worst;
            self.outcome = candidate;
        }
    }

    /// Takes the iterate out, to end the iteration with it.
    fn take(&mut self) -> Outcome {
        std::mem::replace(
            &mut self.outcome,
            Outcome {
                x: Vec::new(),
                multipliers: Vec::new(),
                status: QpStatus::MaxIterations,
                iterations: 0,
                message: String::new(),
            },
        )
    }
}

/// What the iteration hands back to the backend.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// Primal x.
    pub x: Vec<f64>,
    /// Multipliers λ ≥ 0.
    pub multipliers: Vec<f64>,
    /// The method's verdict.
    pub status: QpStatus,
    /// Active-set iterations (each a numeric factorisation or a low-rank update).
    pub iterations: usize,
    /// Why it stopped.
    pub message: String,
}

/// The state of one solve: the problem, its fixed-pattern KKT matrix and factor.
pub struct ActiveSet<'p> {
    problem: &'p QpProblem,
    settings: &'p PdasSettings,
    options: &'p SolveOptions,
    start: Instant,
    scales: Arc<ResidualScales>,
    kkt: KktMatrix,
    factor: KktFactor,
    /// Solves with the current factor kept for low-rank updates.
    cache: ColumnCache,
    /// Mean |Aⱼⱼ|, the stiffness unit the relative settings refer to.
    stiffness: f64,
    refinement_steps: usize,
    factorisations: usize,
    updates: usize,
    /// Time from the start of the solve to the end of the setup (checks, K's pattern, the
    /// ordering, the symbolic analysis, the memory check and the allocation).
    analysis: Duration,
    /// Total time in numeric factorisations.
    factor_time: Duration,
    /// Per row, its multiplier law.  A box row is *active* when it sticks (B x = g on it) and
    /// inactive when it slips, with λ fixed at ±s (Tresca) or tied to ±μ λₙ (Coulomb).
    laws: Vec<Law>,
    /// The Coulomb rows, when the problem is solved with Coulomb's bounds.
    coulomb: Option<&'p CoulombRows>,
    /// B in compressed-row form, for the coupling of slipping Coulomb rows.
    rows_of_b: Option<CscMatrix>,
}

/// A row's multiplier law.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Law {
    /// λ ≥ 0.
    OneSided,
    /// |λ| ≤ s.
    Tresca(f64),
    /// |λ| ≤ μ max(0, λ of the normal row).
    Coulomb {
        /// The normal row.
        normal: usize,
        /// μ.
        mu: f64,
    },
}

/// A set's solution measured against the KKT conditions (see [`ActiveSet::measure`]).
struct Measured {
    /// (x, max(λ, 0)) as an answer, status `solved`.
    candidate: Outcome,
    /// Its KKT residuals.
    residuals: KktResiduals,
    /// Their worst scaled entry.
    worst: f64,
    /// Rows in which the predicted set differs from the solved one.
    changes: usize,
}

/// Measured cost of the last factorisation and of one solve with it.
#[derive(Debug, Default)]
struct Timing {
    factor: Duration,
    solve: Duration,
    /// One column of a batched solve.
    column: Duration,
}

impl<'p> ActiveSet<'p> {
    /// Builds K's pattern and its symbolic factor (ordering + analysis), then checks that the
    /// numeric factor fits in memory and allocates it.
    pub fn new(
        problem: &'p QpProblem,
        settings: &'p PdasSettings,
        options: &'p SolveOptions,
        start: Instant,
        coulomb: Option<&'p CoulombRows>,
    ) -> Result<Self, SetupError> {
        let (mut factor, kkt) = KktFactor::analyse(problem)?;
        let (dim, nnz_l) = (kkt.dim(), factor.nnz_l());
        // The factor and faer's workspace, plus K and about ten vectors of length n + m: the
        // figure `memory_need` prices too.
        let bytes = crate::memory::setup_bytes(&factor, &kkt);
        signorini_qp::memory::check_fits(
            "pdas",
            || format!("the LDLᵀ factor of the {dim}×{dim} KKT matrix (nnz(L) = {nnz_l:.3e})"),
            bytes,
        )
        .map_err(SetupError::TooLarge)?;
        factor.allocate()?;
        let n = problem.dofs();
        let diagonal_sum: f64 = kkt.a_diagonal().iter().map(|a| a.abs()).sum();
        let stiffness = if n > 0 && diagonal_sum > 0.0 && diagonal_sum.is_finite() {
            diagonal_sum / n as f64
        } else {
            1.0
        };
        Ok(Self {
            problem,
            settings,
            options,
            start,
            scales: options.residual_scales(problem),
            kkt,
            factor,
            cache: ColumnCache::default(),
            stiffness,
            refinement_steps: 0,
            factorisations: 0,
            updates: 0,
            analysis: start.elapsed(),
            factor_time: Duration::ZERO,
            laws: laws(problem, coulomb),
            coulomb,
            rows_of_b: coulomb.map(|_| problem.constraints.to_csr()),
        })
    }

    /// "ordering amd, nnz(L) 1.2e6" for messages.
    pub fn describe_factor(&self) -> String {
        format!(
            "ordering {}, nnz(L) {:.3e}",
            self.factor.method(),
            self.factor.nnz_l() as f64
        )
    }

    /// The warm start, when one is given and fits the problem.
    fn warm_start(&self) -> Option<&signorini_qp::WarmStart> {
        self.options
            .warm_start
            .as_deref()
            .and_then(|w| w.fitting(self.problem))
    }

    /// Whether the iteration starts with the interior-point predictor ([`StartSet::Interior`],
    /// or [`StartSet::Auto`] on an interface where fewer than half the one-sided rows touch
    /// first) rather than with a set: never with a warm start, with box rows or without rows.
    fn starts_interior(&self) -> bool {
        if self.warm_start().is_some() || self.has_box() || self.problem.rows() == 0 {
            return false;
        }
        match self.settings.start {
            StartSet::Interior => true,
            StartSet::Auto => {
                let touching = signorini_qp::first_touch(self.problem)
                    .into_iter()
                    .filter(|t| *t)
                    .count();
                2 * touching < self.problem.rows()
            }
            StartSet::All | StartSet::ClosedGaps | StartSet::Empty => false,
        }
    }

    /// The first set and its signs: predicted from the warm start when there is one (the
    /// previous load increment's answer), else from the settings ([`StartSet::Interior`] and
    /// [`StartSet::Auto`] start from every row when they come here: with box rows, or on a
    /// flush interface).
    fn first_set(&self) -> (Vec<bool>, Vec<f64>) {
        let p = self.problem;
        if let Some(start) = self.warm_start() {
            let guess = SetSolution {
                x: start.x.clone(),
                multipliers: start.multipliers.clone(),
                steps: 0,
                residual: f64::NAN,
                timed_out: false,
                correction: Vec::new(),
            };
            if guess.is_finite() {
                return self.next_state(&guess);
            }
        }
        let active = match self.settings.start {
            StartSet::Empty => vec![false; p.rows()],
            StartSet::All | StartSet::Interior | StartSet::Auto => vec![true; p.rows()],
            StartSet::ClosedGaps => p
                .gap
                .iter()
                .zip(&self.scales.rows)
                .map(|(g, x)| *g <= self.settings.closed_gap * x)
                .collect(),
        };
        (active, vec![0.0; p.rows()])
    }

    fn deadline(&self) -> Option<Instant> {
        self.options.time_limit.map(|t| self.start + t)
    }

    fn out_of_time(&self) -> bool {
        self.deadline().is_some_and(|d| Instant::now() >= d)
    }

    /// Numeric factorisation of K for `active` with −`delta` on the active multiplier rows and
    /// the primal regularisation `rho`; returns its duration.
    fn factorise_with(
        &mut self,
        active: &[bool],
        delta: f64,
        rho: f64,
    ) -> Result<Duration, PdasError> {
        let clock = Instant::now();
        self.kkt
            .set_values(active, rho, delta, 1.0 / self.stiffness);
        self.factor_values(clock)
    }

    /// ρ: the primal regularisation, only when A has a kernel.
    fn rho(&self) -> f64 {
        if self.problem.kernel.is_empty() {
            0.0
        } else {
            self.settings.primal_regularization * self.stiffness
        }
    }

    /// Numeric factorisation of K with the values it holds; returns the time since `clock`.
    fn factor_values(&mut self, clock: Instant) -> Result<Duration, PdasError> {
        let s = self.stiffness;
        // Dynamic regularisation is a safety net below every static pivot: a primal pivot
        // under 1e-3 ρ (relative), or a multiplier pivot under 1e-3 δ, is replaced.
        let floor = 1e-3
            * self
                .settings
                .primal_regularization
                .min(self.settings.dual_regularization);
        let epsilon = floor * s.min(1.0 / s);
        self.factor.factor(&self.kkt, epsilon, 1e3 * epsilon)?;
        self.factorisations += 1;
        self.factor_time += clock.elapsed();
        Ok(clock.elapsed())
    }

    /// δ in the problem's units (compliance).
    fn delta(&self) -> f64 {
        self.settings.dual_regularization / self.stiffness
    }

    /// The next set and, per row, the sign of a slipping box row's fixed multiplier (0
    /// otherwise): with vᵢ = λᵢ + c (Bx − g)ᵢ, a one-sided row is active when vᵢ > 0 by more
    /// than a negligible force ([`NEGLIGIBLE`] × tol × its force scale); a box
    /// row of bound sᵢ sticks (active) when |vᵢ| ≤ sᵢ and slips with λᵢ = sᵢ sign vᵢ otherwise
    /// — the semismooth Newton step on λ = P_[−s, s](λ + c r) (Hüeber, Stadler and Wohlmuth).
    fn next_state(&self, solution: &SetSolution) -> (Vec<bool>, Vec<f64>) {
        let p = self.problem;
        let c = self.settings.penalty * self.stiffness;
        let bx = mat_vec(&p.constraints, &solution.x);
        let v: Vec<f64> = solution
            .multipliers
            .iter()
            .zip(&bx)
            .zip(&p.gap)
            .map(|((l, b), g)| l + c * (b - g))
            .collect();
        let negligible = NEGLIGIBLE * self.options.tol;
        let mut signs = vec![0.0; p.rows()];
        let active = v
            .iter()
            .zip(&self.laws)
            .zip(signs.iter_mut())
            .enumerate()
            .map(|(i, ((&vi, law), sign))| {
                // Coulomb's bound comes from the normal row's own predictor: μ max(0, vₙ); a
                // row whose normal row opens is free (λ = 0), neither sticking nor slipping.
                let bound = match *law {
                    Law::OneSided => return vi > negligible * self.scales.row_forces[i],
                    Law::Tresca(s) => s,
                    Law::Coulomb { normal, mu } if v[normal] > 0.0 => mu * v[normal],
                    Law::Coulomb { .. } => return false,
                };
                if vi.abs() <= bound {
                    true
                } else {
                    *sign = vi.signum();
                    false
                }
            })
            .collect();
        (active, signs)
    }

    /// Whether the problem has box rows (then the sets carry signs and the interior-point
    /// continuation, which knows one-sided rows only, is not used).
    fn has_box(&self) -> bool {
        self.laws.iter().any(|l| *l != Law::OneSided)
    }

    /// The fixed multipliers of the inactive rows of a set: ±s on slipping Tresca rows, else 0
    /// (a slipping Coulomb row's multiplier is tied to its normal row by [`Self::coupling`]).
    fn fixed(&self, active: &[bool], signs: &[f64]) -> Vec<f64> {
        active
            .iter()
            .zip(signs)
            .zip(&self.laws)
            .map(|((&on, sign), law)| match law {
                Law::Tresca(s) if !on => sign * s,
                _ => 0.0,
            })
            .collect()
    }

    /// The slipping Coulomb rows of a set whose normal rows are active, tied by λ = μ σ λₙ.
    fn coupling(&self, active: &[bool], signs: &[f64]) -> Option<Coupling> {
        let rows_of_b = self.rows_of_b.as_ref()?;
        let links: Vec<(usize, usize, f64)> = self
            .laws
            .iter()
            .enumerate()
            .filter_map(|(i, law)| match *law {
                Law::Coulomb { normal, mu } if !active[i] && signs[i] != 0.0 && active[normal] => {
                    Some((i, normal, mu * signs[i]))
                }
                _ => None,
            })
            .collect();
        (!links.is_empty()).then(|| Coupling::new(&links, rows_of_b, self.problem.dofs()))
    }

    /// λ projected onto each row's multiplier set: [0, ∞), [−s, s] or [−μ λₙ⁺, μ λₙ⁺].
    fn clamp(&self, multipliers: &[f64]) -> Vec<f64> {
        multipliers
            .iter()
            .zip(&self.laws)
            .map(|(&l, law)| match *law {
                Law::OneSided => RowSet::NonNegative.project(l),
                Law::Tresca(s) => RowSet::Box(s).project(l),
                Law::Coulomb { normal, mu } => {
                    RowSet::Box(mu * multipliers[normal].max(0.0)).project(l)
                }
            })
            .collect()
    }

    /// Whether to reach `active` from the factored set by a low-rank update rather than a
    /// factorisation: few changed rows, and their solves cheaper than a factorisation.
    /// `batched`: the set's first solve joins the batch of the missing columns (no Coulomb
    /// coupling), so it costs a column rather than a solve of its own.
    fn prefer_update(
        &self,
        factored: &[bool],
        active: &[bool],
        timing: &Timing,
        batched: bool,
    ) -> bool {
        let (rank, missing) = self.cache.need(factored, active);
        let dim = self.kkt.dim() as f64;
        // Memory: the stored columns never outgrow the factor itself, nor half of what the
        // machine has left.
        let new_bytes = missing as f64 * dim * 8.0;
        let fits = ((self.cache.len() + missing) as f64) * dim <= self.factor.nnz_l() as f64
            && signorini_qp::memory::available_bytes()
                .is_none_or(|free| new_bytes <= 0.5 * free as f64);
        // Time: the missing columns (one batched solve), then the solves of the iteration
        // (one, and one or two of refinement once the set settles: two on average) with the
        // correction of `rank` dense columns each, against a factorisation and plain solves.
        // A batched first solve is one more column of the batch instead of a solve.
        let solve = timing.solve.as_secs_f64();
        let column = timing.column.as_secs_f64();
        let correction = rank as f64 * dim * 1e-9;
        let cost = if batched {
            (missing + 1) as f64 * column + solve + 2.0 * correction
        } else {
            missing as f64 * column + 2.0 * (solve + correction)
        };
        rank > 0
            && rank <= self.settings.max_update_rank
            && fits
            && cost < timing.factor.as_secs_f64() + 2.0 * solve
    }

    /// When the refinement of a set's solution stops.
    fn limits(&self) -> Limits {
        Limits {
            max_steps: self.settings.refinement_steps,
            target: self.settings.refinement_target * self.options.tol,
            deadline: self.deadline(),
        }
    }

    /// Measures a set's solution (x, λ) and the set `next` it predicts: (x, max(λ, 0)) as a
    /// candidate answer at `iteration`, its KKT residuals, and the rows that change.
    fn measure(
        &self,
        x: Vec<f64>,
        multipliers: &[f64],
        set: &[bool],
        next: &[bool],
        iteration: usize,
    ) -> Measured {
        let clamped = self.clamp(multipliers);
        let residuals = match self.coulomb {
            Some(rows) => rows.residuals(self.problem, &self.scales, &x, &clamped),
            None => kkt_residuals_with(self.problem, &self.scales, &x, &clamped),
        };
        let worst = residuals.worst();
        let changes = next.iter().zip(set).filter(|(a, b)| a != b).count();
        Measured {
            candidate: Outcome {
                x,
                multipliers: clamped,
                status: QpStatus::Solved,
                iterations: iteration,
                message: String::new(),
            },
            residuals,
            worst,
            changes,
        }
    }

    /// Ends the iteration with `outcome` as the answer, its status, and the message with the
    /// counts and times of the whole solve.
    fn finish(
        &self,
        mut outcome: Outcome,
        status: QpStatus,
        iterations: usize,
        message: String,
    ) -> Outcome {
        outcome.status = status;
        outcome.iterations = iterations;
        outcome.message = format!(
            "{message}; {iterations} active-set iterations: {} factorisations, {} low-rank updates, {} refinement steps; {}; setup {:.1} ms, factorisations {:.1} ms",
            self.factorisations,
            self.updates,
            self.refinement_steps,
            self.describe_factor(),
            self.analysis.as_secs_f64() * 1e3,
            self.factor_time.as_secs_f64() * 1e3,
        );
        outcome
    }

    /// A certificate of infeasibility in an iterate that does not converge:
    /// * primal: the ray y = Δλ⁺ of the last refinement correction (see
    ///   [`SetSolution::correction`]) or y = λ⁺, checked against B and g by the core's
    ///   [`FarkasRay`] (any feasible x would move ≥ 10⁸ times the displacement that closes
    ///   the ray's gaps);
    /// * dual: the rigid part r of x with fᵀr > 0 and B r ≤ 0 (see [`pushed_away`]).
    fn certificate(
        &self,
        x: &[f64],
        multipliers: &[f64],
        correction: &[f64],
    ) -> Option<(QpStatus, String)> {
        let p = self.problem;
        // Box rows hold no infeasibility (any r is allowed on them): the ray lives on the
        // one-sided rows.
        let one_sided = |y: &[f64]| -> Vec<f64> {
            y.iter()
                .zip(&self.laws)
                .map(|(v, law)| if *law == Law::OneSided { *v } else { 0.0 })
                .collect()
        };
        let rays = [one_sided(correction), one_sided(multipliers)];
        if let Some(ray) = rays
            .iter()
            .filter_map(|y| primal_ray(p, y))
            .find(FarkasRay::proves_infeasibility)
        {
            return Some((
                QpStatus::PrimalInfeasible,
                format!(
                    "primal infeasible: the multipliers give {} (no x satisfies B x ≤ g)",
                    ray.describe()
                ),
            ));
        }
        // A rigid motion against friction is bounded by the slip work Σ s |B r|, which
        // `pushed_away` does not weigh: no dual certificate with box rows.
        if self.has_box() {
            return None;
        }
        let r = rigid_part(&p.kernel, x)?;
        pushed_away(p, &r).map(|work| {
            (QpStatus::DualInfeasible, format!("dual infeasible: a rigid motion r with B r ≤ 0 and fᵀr = {work:.3e} ‖r‖∞ > 0 (a floating body is pushed away from every contact); the objective is unbounded below"))
        })
    }
}

/// The ray y = λ⁺ of the multipliers, measured against B and g.
fn primal_ray(problem: &QpProblem, multipliers: &[f64]) -> Option<FarkasRay> {
    let positive: Vec<f64> = multipliers.iter().map(|l| l.max(0.0)).collect();
    FarkasRay::measure(problem, &positive)
}

/// "; why the multipliers are no certificate" when gᵀλ⁺ < 0 but λ⁺ does not certify
/// infeasibility (nor did the last correction, or [`ActiveSet::certificate`] would have
/// stopped), else "".
/// The message of a set that reproduces itself while its refined answer misses the tolerance
/// (the refinement stopped at the round-off of forming the residuals, or stalled): `rows`
/// active rows, the answer's worst scaled KKT residual `worst`, the refined KKT system's
/// residual `system`, and why no infeasibility certificate was issued.
fn settled_message(
    problem: &QpProblem,
    rows: usize,
    (worst, system): (f64, f64),
    multipliers: &[f64],
) -> String {
    format!(
        "active set of {rows} rows settled but the KKT residuals ({worst:.1e}, refined KKT system {system:.1e}) miss the tolerance{}",
        no_certificate(problem, multipliers)
    )
}

fn no_certificate(problem: &QpProblem, multipliers: &[f64]) -> String {
    primal_ray(problem, multipliers)
        .filter(|ray| ray.gap_fraction > 0.0)
        .and_then(|ray| ray.shortfall())
        .map_or_else(String::new, |why| format!("; {why}"))
}

/// Each row's law: the problem's blocks, with the Coulomb rows of `coulomb` tied to their normal
/// rows.
fn laws(problem: &QpProblem, coulomb: Option<&CoulombRows>) -> Vec<Law> {
    let mut laws: Vec<Law> = row_sets(&problem.blocks)
        .map(|set| match set {
            RowSet::Box(s) => Law::Tresca(s),
            RowSet::NonNegative => Law::OneSided,
        })
        .collect();
    for link in coulomb.map(CoulombRows::links).unwrap_or_default() {
        laws[link.row] = Law::Coulomb {
            normal: link.normal_row,
            mu: link.mu,
        };
    }
    laws
}

fn count(active: &[bool]) -> usize {
    active.iter().filter(|a| **a).count()
}

/// Why the iteration could not start.
#[derive(Debug)]
pub enum SetupError {
    /// The factor would not fit in memory.
    TooLarge(signorini_qp::QpError),
    /// Anything else (pattern, ordering, allocation).
    Pdas(PdasError),
}

impl From<PdasError> for SetupError {
    fn from(e: PdasError) -> Self {
        SetupError::Pdas(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x = (½, ½) puts row 0 of `two_rows` exactly on its gap and row 1 far from it, so
    /// vᵢ = λᵢ on row 0: a multiplier of round-off size (a ten-thousandth of the tolerance
    /// times the row's force scale) does not make the row active; one a hundred times the
    /// negligible force does.  With the rule vᵢ > 0 the round-off one did.
    #[test]
    fn a_multiplier_of_round_off_size_does_not_make_a_row_active() {
        let p = signorini_qp::examples::two_rows().problem;
        let (settings, options) = (PdasSettings::default(), SolveOptions::default());
        let set = ActiveSet::new(&p, &settings, &options, Instant::now(), None).unwrap();
        let force = set.scales.row_forces[0] * options.tol;
        let with = |multiplier: f64| SetSolution {
            x: vec![0.5, 0.5],
            multipliers: vec![multiplier, 0.0],
            steps: 0,
            residual: f64::NAN,
            timed_out: false,
            correction: Vec::new(),
        };
        assert_eq!(set.next_state(&with(0.5)).0, vec![true, false]);
        assert_eq!(set.next_state(&with(1e-4 * force)).0, vec![false, false]);
        assert_eq!(set.next_state(&with(1e-1 * force)).0, vec![true, false]);
    }
}
