//! The one residual check used for every backend.

use serde::Serialize;

use super::ops::{mat_t_vec, mat_vec, norm_inf};
use super::problem::QpProblem;

/// How far (x, λ) is from the KKT conditions.  All but `max_penetration` are dimensionless.
///
/// Every measure is taken against fixed scales of the problem's data (see [`ResidualScales`]),
/// never against the answer itself, so a wrong x cannot scale its own residual down, and every
/// backend is judged by the same yardstick.  With the force scale F and the length scale X:
/// * `max_penetration` = max(0, maxᵢ (Bx − g)ᵢ), in the problem's length unit;
/// * `relative_penetration` = maxᵢ max(0, (Bx − g)ᵢ) / Xᵢ;
/// * `stationarity` = ‖Ax − f + Bᵀλ‖∞ / F;
/// * `complementarity` = maxᵢ |λᵢ (g − Bx)ᵢ| / (F Xᵢ);
/// * `min_multiplier` = min(0, minᵢ λᵢ) / F (zero when every λᵢ ≥ 0).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default, schemars::JsonSchema)]
pub struct KktResiduals {
    /// Largest constraint violation max(0, Bx − g), in length units.
    pub max_penetration: f64,
    /// Largest violation of a row relative to that row's length scale Xᵢ.
    pub relative_penetration: f64,
    /// Relative equilibrium residual ‖Ax − f + Bᵀλ‖∞ / F.
    pub stationarity: f64,
    /// Relative complementarity maxᵢ |λᵢ sᵢ| / (F Xᵢ).
    pub complementarity: f64,
    /// Most negative multiplier relative to F (≤ 0).
    pub min_multiplier: f64,
}

impl KktResiduals {
    /// The residuals of an answer that cannot be measured (wrong lengths, non-finite entries,
    /// or no answer at all): every measure infinite, so no tolerance is met.
    pub const UNMEASURABLE: Self = Self {
        max_penetration: f64::INFINITY,
        relative_penetration: f64::INFINITY,
        stationarity: f64::INFINITY,
        complementarity: f64::INFINITY,
        min_multiplier: f64::NEG_INFINITY,
    };

    /// The worst of the four dimensionless measures; infinite when any of them is NaN
    /// (`f64::max` would silently drop a NaN).
    pub fn worst(&self) -> f64 {
        let all = [
            self.relative_penetration,
            self.stationarity,
            self.complementarity,
            -self.min_multiplier,
        ];
        if all.iter().any(|v| v.is_nan()) {
            return f64::INFINITY;
        }
        all.into_iter().fold(f64::NEG_INFINITY, f64::max)
    }

    /// True when every dimensionless measure is at most `tol` (and none is NaN).
    pub fn meet(&self, tol: f64) -> bool {
        self.worst() <= tol
    }

    /// Multiplies the length-valued field by `length` (to report in the user's units).
    pub fn with_length_scale(mut self, length: f64) -> Self {
        self.max_penetration *= length;
        self
    }
}

/// Smallest scale used as a denominator, so that an all-zero problem gives zero residuals.
const TINY: f64 = 1e-300;

/// The fixed scales residuals are measured against, computed from A, B, f and g only.
///
/// * k̄ = n / Σⱼ 1/|Aⱼⱼ|, the harmonic mean of the diagonal (zero entries skipped; 1 when there
///   is none), and per row i, kᵢ, the same mean over the DOFs row i touches: stiffness units,
///   dominated by the softest DOFs, so that a soft body pressed by a stiff one (contrast 10⁶) is
///   judged by its own displacements — and, per row, only by the bodies that row joins (a soft
///   body elsewhere in the scene must not loosen the check of a stiff pair);
/// * G = max(0, −minᵢ gᵢ), the deepest initial overlap;
/// * X = max(‖f‖₁ / k̄, G) and Xᵢ = max(‖f‖₁ / kᵢ, G) — the displacement the total load would
///   give a spring of that stiffness (independent of the mesh size, unlike ‖f‖∞, which shrinks
///   with the elements), or the overlap to be undone; when zero, ‖g‖∞, and 1 when g is zero too;
/// * F = max(‖f‖∞, k̄ G) — the largest nodal load, or the force of a k̄ spring over the overlap;
///   when both are zero, k̄ X.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResidualScales {
    /// Force scale F (per DOF).
    pub force: f64,
    /// Length scale X of the whole problem.
    pub length: f64,
    /// Length scale Xᵢ of each constraint row.
    pub rows: Vec<f64>,
}

impl ResidualScales {
    /// The scales of `problem` (see the type's docs).
    ///
    /// ```
    /// use signorini_core::qp::{QpProblem, ResidualScales};
    /// use sprs::TriMat;
    /// let mut a = TriMat::new((2, 2)); a.add_triplet(0, 0, 4.0); a.add_triplet(1, 1, 4.0);
    /// let b = TriMat::new((0, 2));
    /// let qp = QpProblem::try_new(a.to_csc(), vec![1.0, -3.0], b.to_csc(), vec![]).unwrap();
    /// let s = ResidualScales::of(&qp);
    /// assert_eq!((s.force, s.length), (3.0, 1.0));
    /// ```
    pub fn of(problem: &QpProblem) -> Self {
        let diag: Vec<f64> = (0..problem.dofs())
            .map(|j| problem.stiffness.get(j, j).copied().unwrap_or(0.0).abs())
            .collect();
        let harmonic = |count: usize, compliance: f64| {
            (count > 0 && compliance > 0.0 && compliance.is_finite())
                .then(|| count as f64 / compliance)
        };
        let (count, compliance) = diag
            .iter()
            .filter(|d| **d > 0.0)
            .fold((0usize, 0.0_f64), |(c, s), d| (c + 1, s + 1.0 / d));
        let stiffness = harmonic(count, compliance).unwrap_or(1.0);
        let overlap = problem.gap.iter().fold(0.0_f64, |m, g| m.max(-g));
        let load_1: f64 = problem.load.iter().map(|v| v.abs()).sum();
        let fallback = {
            let g = norm_inf(&problem.gap);
            if g > 0.0 {
                g
            } else {
                1.0
            }
        };
        let length_for = |k: f64| {
            let x = (load_1 / k).max(overlap);
            if x > 0.0 && x.is_finite() {
                x
            } else if x > 0.0 {
                f64::MAX
            } else {
                fallback
            }
        };
        let length = length_for(stiffness);
        let mut row_count = vec![0usize; problem.rows()];
        let mut row_compliance = vec![0.0_f64; problem.rows()];
        for (j, col) in problem.constraints.outer_iterator().enumerate() {
            if diag[j] > 0.0 {
                for (i, _) in col.iter() {
                    row_count[i] += 1;
                    row_compliance[i] += 1.0 / diag[j];
                }
            }
        }
        let rows = row_count
            .iter()
            .zip(&row_compliance)
            .map(|(&c, &s)| harmonic(c, s).map_or(length, length_for))
            .collect();
        let mut force = norm_inf(&problem.load).max(stiffness * overlap);
        if force == 0.0 {
            force = stiffness * length;
        }
        Self {
            force: force.max(TINY),
            length: length.max(TINY),
            rows,
        }
    }
}

/// The KKT residuals of (x, λ) for `problem`; see [`KktResiduals`] for the definitions.
///
/// ```
/// use signorini_core::qp::{kkt_residuals, QpProblem};
/// use sprs::TriMat;
/// // min x² − 4x  s.t. x ≤ 1  →  x = 1, λ = 2.
/// let mut a = TriMat::new((1, 1)); a.add_triplet(0, 0, 2.0);
/// let mut b = TriMat::new((1, 1)); b.add_triplet(0, 0, 1.0);
/// let qp = QpProblem::try_new(a.to_csc(), vec![4.0], b.to_csc(), vec![1.0]).unwrap();
/// let r = kkt_residuals(&qp, &[1.0], &[2.0]);
/// assert!(r.meet(1e-15));
/// assert!(!kkt_residuals(&qp, &[1.1], &[2.0]).meet(1e-3));
/// ```
pub fn kkt_residuals(problem: &QpProblem, x: &[f64], multipliers: &[f64]) -> KktResiduals {
    kkt_residuals_with(problem, &ResidualScales::of(problem), x, multipliers)
}

/// As [`kkt_residuals`], with the scales computed once by the caller (e.g. a backend that checks
/// the residuals every iteration).
pub fn kkt_residuals_with(
    problem: &QpProblem,
    scales: &ResidualScales,
    x: &[f64],
    multipliers: &[f64],
) -> KktResiduals {
    if x.len() != problem.dofs()
        || multipliers.len() != problem.rows()
        || x.iter().chain(multipliers).any(|v| !v.is_finite())
    {
        return KktResiduals::UNMEASURABLE;
    }
    let ax = mat_vec(&problem.stiffness, x);
    let bx = mat_vec(&problem.constraints, x);
    let btl = mat_t_vec(&problem.constraints, multipliers);
    let force_scale = scales.force;

    let stationarity = ax
        .iter()
        .zip(&problem.load)
        .zip(&btl)
        .map(|((a, f), b)| (a - f + b).abs())
        .fold(0.0, f64::max)
        / force_scale;
    let mut max_penetration = 0.0_f64;
    let mut complementarity = 0.0_f64;
    let mut relative_penetration = 0.0_f64;
    for (((bxi, gi), li), xi) in bx
        .iter()
        .zip(&problem.gap)
        .zip(multipliers)
        .zip(&scales.rows)
    {
        let slack = gi - bxi;
        let xi = xi.max(TINY);
        max_penetration = max_penetration.max(-slack);
        relative_penetration = relative_penetration.max(-slack / xi);
        // F·Xᵢ can underflow to 0 when both are tiny: keep the quotient finite.
        complementarity = complementarity.max((li * slack).abs() / (force_scale * xi).max(TINY));
    }
    let min_multiplier = multipliers.iter().copied().fold(0.0, f64::min) / force_scale;
    let finite_or_inf = |v: f64| if v.is_finite() { v } else { f64::INFINITY };
    KktResiduals {
        max_penetration,
        relative_penetration: finite_or_inf(relative_penetration),
        stationarity: finite_or_inf(stationarity),
        complementarity: finite_or_inf(complementarity),
        min_multiplier,
    }
}
