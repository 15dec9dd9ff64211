//! The one residual check used for every backend.

use serde::Serialize;

use super::ops::{mat_t_vec, mat_vec};
use super::problem::QpProblem;
pub use super::scales::ResidualScales;
use super::scales::TINY;

/// How far (x, λ) is from the KKT conditions.  All but `max_penetration` are dimensionless.
///
/// Every measure is taken against fixed scales of the problem's data (see [`ResidualScales`]),
/// never against the answer itself, so a wrong x cannot scale its own residual down, and every
/// backend is judged by the same yardstick.  With the row length scales Xᵢ and the force scales
/// F_c of each connected component c (row i's component c(i), DOF j's component c(j)):
/// * `max_penetration` = max(0, maxᵢ (Bx − g)ᵢ), in the problem's length unit;
/// * `relative_penetration` = maxᵢ max(0, (Bx − g)ᵢ) / Xᵢ;
/// * `stationarity` = maxⱼ |(Ax − f + Bᵀλ)ⱼ| / F_c(j);
/// * `complementarity` = maxᵢ |λᵢ (g − Bx)ᵢ| / (F_c(i) Xᵢ);
/// * `min_multiplier` = minᵢ min(0, λᵢ / F_c(i)) (zero when every λᵢ ≥ 0).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default, schemars::JsonSchema)]
pub struct KktResiduals {
    /// Largest constraint violation max(0, Bx − g), in length units.
    pub max_penetration: f64,
    /// Largest violation of a row relative to that row's length scale Xᵢ.
    pub relative_penetration: f64,
    /// Relative equilibrium residual maxⱼ |(Ax − f + Bᵀλ)ⱼ| / F_c(j).
    pub stationarity: f64,
    /// Relative complementarity maxᵢ |λᵢ sᵢ| / (F_c(i) Xᵢ).
    pub complementarity: f64,
    /// Most negative multiplier relative to its component's force scale (≤ 0).
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
        || scales.dof_forces.len() != problem.dofs()
        || scales.rows.len() != problem.rows()
        || x.iter().chain(multipliers).any(|v| !v.is_finite())
    {
        return KktResiduals::UNMEASURABLE;
    }
    let ax = mat_vec(&problem.stiffness, x);
    let bx = mat_vec(&problem.constraints, x);
    let btl = mat_t_vec(&problem.constraints, multipliers);
    let stationarity = ax
        .iter()
        .zip(&problem.load)
        .zip(&btl)
        .zip(&scales.dof_forces)
        .map(|(((a, f), b), force)| (a - f + b).abs() / force)
        .fold(0.0, f64::max);
    let mut max_penetration = 0.0_f64;
    let mut complementarity = 0.0_f64;
    let mut relative_penetration = 0.0_f64;
    let mut min_multiplier = 0.0_f64;
    for ((((bxi, gi), li), xi), force) in bx
        .iter()
        .zip(&problem.gap)
        .zip(multipliers)
        .zip(&scales.rows)
        .zip(&scales.row_forces)
    {
        let slack = gi - bxi;
        let xi = xi.max(TINY);
        max_penetration = max_penetration.max(-slack);
        relative_penetration = relative_penetration.max(-slack / xi);
        // F·Xᵢ can underflow to 0 when both are tiny: keep the quotient finite.
        complementarity = complementarity.max((li * slack).abs() / (force * xi).max(TINY));
        min_multiplier = min_multiplier.min(li / force);
    }
    let finite_or_inf = |v: f64| if v.is_finite() { v } else { f64::INFINITY };
    KktResiduals {
        max_penetration,
        relative_penetration: finite_or_inf(relative_penetration),
        stationarity: finite_or_inf(stationarity),
        complementarity: finite_or_inf(complementarity),
        min_multiplier,
    }
}
