//! The one check of a primal-infeasibility certificate, used by every backend that reports
//! `primal-infeasible` from its own iterates (the dual methods, pdas).
//!
//! # Why a ray proves infeasibility (Farkas)
//! If y ≥ 0 and x satisfies B x ≤ g, then yᵀB x ≤ yᵀg, i.e. (Bᵀy)ᵀx ≤ gᵀy, so
//!
//! ```text
//! −gᵀy ≤ −(Bᵀy)ᵀx ≤ Σⱼ |(Bᵀy)ⱼ| |xⱼ| ≤ ‖Bᵀy‖₁ ‖x‖∞.
//! ```
//!
//! With Bᵀy = 0 and gᵀy < 0 no x is feasible.  In floating point Bᵀy is never exactly zero for
//! a ray an iteration found, so the bound is used as it stands: every feasible x has
//! ‖x‖∞ ≥ R = −gᵀy / ‖Bᵀy‖₁.  R is compared with the displacement that closes the certificate
//! rows' own gaps, L = Σᵢ yᵢ |gᵢ| / Σᵢⱼ yᵢ |Bᵢⱼ| (a y-weighted mean of |gᵢ| / ‖Bᵢ‖₁), through
//! two dimensionless numbers of the ray:
//!
//! * the gap fraction κ = −gᵀy / Σᵢ |gᵢ| yᵢ ∈ [−1, 1]: how much of the weighted gaps does not
//!   cancel (1 when every row of the ray overlaps);
//! * the cancellation τ = ‖Bᵀy‖₁ / Σᵢⱼ |Bᵢⱼ| yᵢ ∈ [0, 1]: how far the rows fail to cancel
//!   (0 for an exact ray; O(1) for rows on different unknowns).
//!
//! R / L = κ / τ, the *reach*: every x with B x ≤ g moves at least `reach` times the
//! displacement that closes the gaps of the rows the ray weighs.  The ray is a certificate when
//! the reach is at least [`FARKAS_MARGIN`] (10⁸) after round-off is counted against it (below).
//! So `primal-infeasible` means: no x is feasible, or a feasible x would have to be 10⁸ times
//! longer than the gaps it closes — far outside small-strain linear elasticity, and at a size
//! where B x − g is evaluated with a round-off of 10⁸ ε ≈ 2e-8 of the gaps.  (Equivalently:
//! y is an exact Farkas certificate of the problem with every Bᵢⱼ perturbed by at most a
//! relative τ, which keeps g's rows as they are: B′ᵢⱼ = Bᵢⱼ − (Bᵀy)ⱼ |Bᵢⱼ| / Σₖ |Bₖⱼ| yₖ gives
//! B′ᵀy = 0.)
//!
//! # Round-off
//! Each sum is formed by recursive summation, whose error is at most γₖ times the sum of the
//! absolute values of its k terms, γₖ = k u / (1 − k u), u = ε/2 (Higham, *Accuracy and
//! Stability of Numerical Algorithms*, 2nd ed., §3.1).  With γ = γ_K for K = max(m, n) + 2 (no
//! sum here has more terms), the measured κ̂ and τ̂ are replaced by the bounds
//!
//! ```text
//! κ ≥ κ̂ (1 − γ) − γ,      τ ≤ (τ̂ + γ)(1 + 3γ),
//! ```
//!
//! so an exact ray on exactly cancelling rows (x ≤ −1 and −x ≤ −1) has τ ≤ ~γ and a reach of
//! ~1/γ ≈ 10¹⁵, while a gap sum that is negative only by round-off gets κ ≤ 0 and proves
//! nothing.  The criterion is invariant to a positive scaling of y and of any row (Bᵢ, gᵢ).

use super::ops::{dot, mat_t_vec};
use super::problem::QpProblem;

/// The reach κ/τ a ray needs to certify infeasibility (see the module docs): every feasible x
/// would move at least this many times the displacement that closes the ray's gaps.
pub const FARKAS_MARGIN: f64 = 1e8;

/// The words before the reach in [`FarkasRay::describe`].
const REACH_TEXT: &str = "would move ≥ ";

/// What a candidate ray y ≥ 0 proves about the constraints B x ≤ g, with round-off counted
/// against it (see the module docs for the definitions and the criterion).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FarkasRay {
    /// Lower bound of κ = −gᵀy / Σᵢ |gᵢ| yᵢ (positive when the weighted gaps overlap).
    pub gap_fraction: f64,
    /// Upper bound of τ = ‖Bᵀy‖₁ / Σᵢⱼ |Bᵢⱼ| yᵢ (zero only for rows without any entry).
    pub cancellation: f64,
}

impl FarkasRay {
    /// Measures the ray `y` against `problem`'s B and g; `None` when y has the wrong length, a
    /// negative or non-finite entry, or no positive entry.
    ///
    /// ```
    /// use signorini_qp::{FarkasRay, QpProblem};
    /// use sprs::TriMat;
    /// // x ≤ −1 and −x ≤ −1: y = (1, 1) gives Bᵀy = 0, gᵀy = −2.
    /// let mut a = TriMat::new((1, 1)); a.add_triplet(0, 0, 1.0);
    /// let mut b = TriMat::new((2, 1)); b.add_triplet(0, 0, 1.0); b.add_triplet(1, 0, -1.0);
    /// let qp = QpProblem::try_new(a.to_csc(), vec![0.0], b.to_csc(), vec![-1.0, -1.0]).unwrap();
    /// let ray = FarkasRay::measure(&qp, &[1.0, 1.0]).unwrap();
    /// assert!(ray.proves_infeasibility());
    /// assert!(!FarkasRay::measure(&qp, &[1.0, 0.0]).unwrap().proves_infeasibility());
    /// ```
    pub fn measure(problem: &QpProblem, y: &[f64]) -> Option<Self> {
        if y.len() != problem.rows() || y.iter().any(|v| !v.is_finite() || *v < 0.0) {
            return None;
        }
        let size = y.iter().copied().fold(0.0_f64, f64::max);
        if size <= 0.0 {
            return None;
        }
        // Scaled to ‖y‖∞ = 1 so that no product overflows; the ray checked is this one.
        let y: Vec<f64> = y.iter().map(|v| v / size).collect();
        let gap_weight: f64 = problem.gap.iter().zip(&y).map(|(g, v)| g.abs() * v).sum();
        let row_weight: f64 = absolute_row_sums(problem)
            .iter()
            .zip(&y)
            .map(|(b, v)| b * v)
            .sum();
        let residual: f64 = mat_t_vec(&problem.constraints, &y)
            .iter()
            .map(|v| v.abs())
            .sum();
        let gamma = gamma(problem.rows().max(problem.dofs()) + 2);
        let kappa = if gap_weight > 0.0 {
            -dot(&problem.gap, &y) / gap_weight
        } else {
            0.0
        };
        let tau = if row_weight > 0.0 {
            residual / row_weight
        } else {
            0.0
        };
        let gap_fraction = kappa * (1.0 - gamma) - gamma;
        let cancellation = if row_weight > 0.0 {
            (tau + gamma) * (1.0 + 3.0 * gamma)
        } else {
            0.0
        };
        (gap_fraction.is_finite() && cancellation.is_finite()).then_some(Self {
            gap_fraction,
            cancellation,
        })
    }

    /// κ / τ: every feasible x moves at least this many times the displacement that closes the
    /// ray's gaps (infinite for rows without entries, which no x can move).
    pub fn reach(&self) -> f64 {
        if self.gap_fraction <= 0.0 {
            0.0
        } else if self.cancellation == 0.0 {
            f64::INFINITY
        } else {
            self.gap_fraction / self.cancellation
        }
    }

    /// True when the ray certifies primal infeasibility: κ > 0 beyond round-off and
    /// reach ≥ [`FARKAS_MARGIN`].
    pub fn proves_infeasibility(&self) -> bool {
        self.gap_fraction > 0.0 && self.reach() >= FARKAS_MARGIN
    }

    /// The numbers of the ray for a message: "… gap fraction … cancellation … a feasible x
    /// would move ≥ R times …" (read back by [`FarkasRay::reported_reach`]).
    pub fn describe(&self) -> String {
        format!(
            "y ≥ 0 with gap fraction −gᵀy/Σ|gᵢ|yᵢ ≥ {:.3e} and cancellation ‖Bᵀy‖₁/Σ|Bᵢⱼ|yᵢ ≤ {:.1e}: a feasible x {REACH_TEXT}{:.1e} times the displacement that closes these rows' gaps",
            self.gap_fraction,
            self.cancellation,
            self.reach()
        )
    }

    /// The reach R a message holding [`FarkasRay::describe`]'s text reports, `None` when it
    /// holds none: for a caller (a test, a report reader) that checks a backend's verdict.
    pub fn reported_reach(message: &str) -> Option<f64> {
        let tail = message.split(REACH_TEXT).nth(1)?;
        tail.split(' ').next()?.parse().ok()
    }

    /// Why the ray is not a certificate, for the message of a non-converged solve (`None` when
    /// it is one).
    pub fn shortfall(&self) -> Option<String> {
        if self.proves_infeasibility() {
            None
        } else if self.gap_fraction <= 0.0 {
            Some(format!(
                "the multipliers' ray y ≥ 0 has gᵀy not negative beyond round-off (gap fraction {:.1e}): no certificate of primal infeasibility",
                self.gap_fraction
            ))
        } else {
            Some(format!(
                "the multipliers' ray y ≥ 0 has gᵀy < 0, but Bᵀy cancels only to {:.1e} of Σ|Bᵢⱼ|yᵢ (reach {:.1e} < {FARKAS_MARGIN:.0e}): a feasible x may exist, so this is no certificate of primal infeasibility",
                self.cancellation,
                self.reach()
            ))
        }
    }
}

/// ‖Bᵢ‖₁ for every row i.
fn absolute_row_sums(problem: &QpProblem) -> Vec<f64> {
    let mut sums = vec![0.0; problem.rows()];
    for col in problem.constraints.outer_iterator() {
        for (i, b) in col.iter() {
            sums[i] += b.abs();
        }
    }
    sums
}

/// γₖ = k u / (1 − k u), u = ε / 2: the relative error bound of a recursive sum of k terms.
fn gamma(k: usize) -> f64 {
    let ku = k as f64 * 0.5 * f64::EPSILON;
    if ku < 1.0 {
        ku / (1.0 - ku)
    } else {
        f64::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::examples::qp_from_triplets;

    /// Two unit springs u₀, u₁ with the contact rows u₀ − u₁ ≤ g₀ (keep a gap) and
    /// u₁ − u₀ ≤ g₁ (overlap by at most −g₁): infeasible exactly when g₀ + g₁ < 0.
    fn overlap_and_separate(g0: f64, g1: f64, eta: f64) -> QpProblem {
        qp_from_triplets(
            2,
            &[(0, 0, 1.0), (1, 1, 1.0)],
            vec![0.0, 0.0],
            2,
            &[(0, 0, 1.0), (0, 1, -1.0), (1, 0, -1.0), (1, 1, 1.0 + eta)],
            vec![g0, g1],
        )
        .unwrap()
    }

    #[test]
    fn an_exact_ray_on_contradicting_rows_is_a_certificate() {
        // κ = 0.2 / 0.2 = 1, τ = 0 up to round-off: the reach is ~1/γ₄ ≈ 2e15.
        let ray = FarkasRay::measure(&overlap_and_separate(-0.1, -0.1, 0.0), &[3.0, 3.0]).unwrap();
        assert!(ray.proves_infeasibility(), "{ray:?}");
        assert!(
            ray.gap_fraction > 1.0 - 1e-15 && ray.reach() > 1e15,
            "{ray:?}"
        );
        assert!(ray.shortfall().is_none());
        let reported = FarkasRay::reported_reach(&format!("infeasible: {}; more", ray.describe()));
        assert!(
            (reported.unwrap() / ray.reach() - 1.0).abs() < 0.1,
            "{ray:?}"
        );
        assert_eq!(FarkasRay::reported_reach("solved"), None);
    }

    #[test]
    fn a_gap_sum_negative_only_by_round_off_proves_nothing() {
        // g₀ + g₁ = 0 exactly (the rows touch, x = (0.5, −0.5)-like points are feasible).
        let ray = FarkasRay::measure(&overlap_and_separate(0.5, -0.5, 0.0), &[1.0, 1.0]).unwrap();
        assert!(!ray.proves_infeasibility(), "{ray:?}");
        assert!(ray.shortfall().unwrap().contains("not negative"));
    }

    #[test]
    fn nearly_parallel_feasible_rows_are_not_certified() {
        // u₀ − u₁ ≤ −1, −u₀ + (1 + η) u₁ ≤ −1 is feasible (u₁ ≤ −2/η) but only at 2/η: the
        // ray (1, 1) has κ = 1 and τ = η / (4 + η), a reach of (4 + η)/η — 4e4 for η = 1e-4,
        // far below 1e8, and the bound R = 2/η equals the nearest feasible |u₁| exactly.
        let eta = 1e-4;
        let ray = FarkasRay::measure(&overlap_and_separate(-1.0, -1.0, eta), &[1.0, 1.0]).unwrap();
        assert!(!ray.proves_infeasibility(), "{ray:?}");
        let expected = (4.0 + eta) / eta;
        assert!((ray.reach() / expected - 1.0).abs() < 1e-10, "{ray:?}");
        assert!(ray.shortfall().unwrap().contains("cancels only"));
    }

    #[test]
    fn a_row_without_entries_and_a_negative_gap_is_infeasible_outright() {
        // 0 · u ≤ −1.
        let p = qp_from_triplets(1, &[(0, 0, 1.0)], vec![0.0], 1, &[], vec![-1.0]).unwrap();
        let ray = FarkasRay::measure(&p, &[1.0]).unwrap();
        assert_eq!(ray.reach(), f64::INFINITY);
        assert!(ray.proves_infeasibility());
    }

    #[test]
    fn the_criterion_ignores_the_size_of_y_and_of_a_row() {
        let p = overlap_and_separate(-1.0, -1.0, 1e-4);
        let a = FarkasRay::measure(&p, &[1.0, 1.0]).unwrap();
        let b = FarkasRay::measure(&p, &[1e-200, 1e-200]).unwrap();
        assert_eq!(a, b);
        // Row 0 times 1e6 (B and g): the ray (1e-6, 1) is the same certificate.
        let scaled = qp_from_triplets(
            2,
            &[(0, 0, 1.0), (1, 1, 1.0)],
            vec![0.0, 0.0],
            2,
            &[(0, 0, 1e6), (0, 1, -1e6), (1, 0, -1.0), (1, 1, 1.0 + 1e-4)],
            vec![-1e6, -1.0],
        )
        .unwrap();
        let c = FarkasRay::measure(&scaled, &[1e-6, 1.0]).unwrap();
        assert!((c.reach() / a.reach() - 1.0).abs() < 1e-9, "{a:?} {c:?}");
    }

    #[test]
    fn what_is_not_a_ray_is_refused() {
        let p = overlap_and_separate(-1.0, -1.0, 0.0);
        assert!(FarkasRay::measure(&p, &[1.0]).is_none());
        assert!(FarkasRay::measure(&p, &[1.0, -1.0]).is_none());
        assert!(FarkasRay::measure(&p, &[0.0, 0.0]).is_none());
        assert!(FarkasRay::measure(&p, &[f64::NAN, 1.0]).is_none());
    }
}
