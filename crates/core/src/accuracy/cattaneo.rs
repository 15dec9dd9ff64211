//! Cattaneo–Mindlin partial slip (Johnson 1985, §7.1, in 2-D): the errors of a frictional Hertz
//! contact that was pressed and then sheared.
//!
//! With P and Q < μP the normal and tangential force per unit length, a = √(4PR/(πE*)) and
//! p₀ = 2P/(πa), the stick zone is |x| < c = a √(1 − Q/(μP)) and the tangential traction
//!
//! ```text
//! q(x) = μ p₀/a (√(a² − x²) − √(c² − x²))   for |x| < c,
//! q(x) = μ p(x) = μ p₀/a √(a² − x²)          for c ≤ |x| < a,
//! ```
//!
//! P and Q are the pair's own forces (Σλₙ and Σλₜ of the run): a shift prescribed as a
//! displacement transmits a force that depends on the bodies' compliance, which the 2-D theory
//! leaves undetermined (a 2-D half-space's displacements are defined only up to a constant).
//! The traction's sign follows Q's: the report's tangent t = (n_y, −n_x) may point either way.
//!
//! **Stick half-width c, from the second moment of μλₙ − λₜ.**  μp − q is zero in the slip
//! zones and q* = μ p₀ (c/a) √(1 − x²/c²) in the stick zone: an ellipse of half-width c, so the
//! Hertz estimator ([`super::moment_half_width`]) applies to the nodal forces
//! λⱼ* = μλₙⱼ − λₜⱼ (negative round-off counted as 0; at slipping nodes |λₜ| = μλₙ to the
//! solver's tolerance, so they add only round-off), with the same bias, (1/3)(h/c)² on a
//! uniform interface mesh.  It needs no node states, and no single node next to x = ±c (where
//! q has an infinite slope) decides it.
//!
//! **Traction profile.**  The rms relative error over the contact zone,
//! √(Σⱼ wⱼ (s qⱼ − q(dⱼ))² / Σⱼ wⱼ q(dⱼ)²) over the slave nodes with dⱼ < a (wⱼ the node's
//! weight, so that the sums approximate integrals on a graded mesh; s the sign of Q; dⱼ the
//! distance to the reference centre).  It is pointwise: the nodes next to the square-root
//! cusps at ±c and ±a carry most of it.

use super::{AccuracyError, NodeSample};
use crate::geometry::Point;
use crate::scene::Cattaneo;

/// Cattaneo's answer for one run's forces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Theory {
    /// Hertz half-width a = √(4PR/(πE*)).
    pub a: f64,
    /// Hertz peak pressure p₀ = 2P/(πa).
    pub p0: f64,
    /// Stick half-width c = a √(1 − |Q|/(μP)).
    pub c: f64,
    /// Coulomb's μ.
    pub mu: f64,
    /// The sign of Q along the report's tangents (+1 when Q = 0).
    pub sign: f64,
}

impl Theory {
    /// Cattaneo's answer for normal force `normal` (P > 0) and tangential force `tangential`;
    /// `None` when P ≤ 0 or |Q| ≥ μP (no stick zone).
    pub fn new(c: &Cattaneo, normal: f64, tangential: f64) -> Option<Theory> {
        let ratio = tangential.abs() / (c.friction * normal);
        if !(normal > 0.0 && normal.is_finite() && ratio < 1.0) {
            return None;
        }
        let a = (4.0 * normal * c.radius / (std::f64::consts::PI * c.contact_modulus)).sqrt();
        Some(Theory {
            a,
            p0: 2.0 * normal / (std::f64::consts::PI * a),
            c: a * (1.0 - ratio).sqrt(),
            mu: c.friction,
            sign: if tangential < 0.0 { -1.0 } else { 1.0 },
        })
    }

    /// |q| at distance `x` from the centre (0 beyond a).
    pub fn traction(&self, x: f64) -> f64 {
        let root = |r: f64| (r * r - x * x).max(0.0).sqrt();
        let slip = self.mu * self.p0 / self.a * root(self.a);
        if x.abs() < self.c {
            slip - self.mu * self.p0 / self.a * root(self.c)
        } else {
            slip
        }
    }
}

/// Cattaneo's answer for one pair's nodes: P = Σ max(λₙ, 0), Q = Σ λₜ.  `pair` is 1-based, for
/// the errors.
pub fn theory_of_nodes(
    c: &Cattaneo,
    nodes: &[NodeSample],
    pair: usize,
) -> Result<Theory, AccuracyError> {
    let normal: f64 = nodes.iter().map(|n| n.multiplier.max(0.0)).sum();
    let mut tangential = 0.0;
    for n in nodes {
        tangential += n
            .tangential_multiplier
            .ok_or(AccuracyError::NoTangential { pair })?;
    }
    if !(normal > 0.0 && normal.is_finite()) {
        return Err(AccuracyError::NoContact { pair });
    }
    Theory::new(c, normal, tangential).ok_or(AccuracyError::FullSlip {
        pair,
        ratio: tangential.abs() / (c.friction * normal),
    })
}

/// c = 2 √(Σ λⱼ* dⱼ² / Σ λⱼ*), λⱼ* = max(0, μ max(λₙⱼ, 0) − s λₜⱼ); `None` when no λⱼ* is
/// positive.  See the [module docs](self).
pub fn stick_half_width(nodes: &[NodeSample], centre: Point, theory: &Theory) -> Option<f64> {
    let (mut force, mut moment) = (0.0, 0.0);
    for n in nodes {
        let t = n.tangential_multiplier.unwrap_or(0.0);
        let l = (theory.mu * n.multiplier.max(0.0) - theory.sign * t).max(0.0);
        let d = crate::geometry::distance(n.position, centre);
        force += l;
        moment += l * d * d;
    }
    (force > 0.0 && force.is_finite()).then(|| 2.0 * (moment / force).sqrt())
}

/// The rms relative error of the tangential traction over the nodes within a of the centre
/// (`None` when Cattaneo's traction is zero there, or no node is).  See the
/// [module docs](self).
pub fn traction_error(nodes: &[NodeSample], centre: Point, theory: &Theory) -> Option<f64> {
    let (mut err, mut norm) = (0.0, 0.0);
    for n in nodes {
        let d = crate::geometry::distance(n.position, centre);
        if d >= theory.a {
            continue;
        }
        let want = theory.traction(d);
        let got = theory.sign * n.tangential_traction.unwrap_or(0.0);
        err += n.weight * (got - want).powi(2);
        norm += n.weight * want * want;
    }
    (norm > 0.0 && norm.is_finite()).then(|| (err / norm).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    const REF: Cattaneo = Cattaneo {
        radius: 1.0,
        contact_modulus: 0.5,
        friction: 0.3,
    };

    /// Composite Simpson, 2 000 panels.
    fn simpson(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
        let n = 2_000;
        let h = (hi - lo) / f64::from(n);
        let mut sum = 0.0;
        for i in 0..=n {
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            sum += w * f(lo + f64::from(i) * h);
        }
        sum * h / 3.0
    }

    #[test]
    fn the_profile_integrates_to_q_and_is_mu_p_outside_the_stick_zone() {
        // ∫q = μP − μp₀πc²/(2a) = μP (1 − c²/a²) = Q: the formula as coded must integrate
        // back to the force it was made from.  Simpson with 2 000 panels on [−c, c] with
        // x = c sin θ and on [c, a] with x = a sin θ (each substitution removes the square-root
        // end inside its piece; the integrands left are smooth: error ≪ 1e-9).
        let (p, q) = (1e-3, 1.8e-4);
        let t = Theory::new(&REF, p, q).unwrap();
        assert!((t.p0 - 2.0 * p / (std::f64::consts::PI * t.a)).abs() < 1e-18);
        let half_pi = std::f64::consts::FRAC_PI_2;
        let inner = simpson(
            |th| t.traction(t.c * th.sin()) * t.c * th.cos(),
            -half_pi,
            half_pi,
        );
        let lo = (t.c / t.a).asin();
        let outer = simpson(
            |th| t.traction(t.a * th.sin()) * t.a * th.cos(),
            lo,
            half_pi,
        );
        let integral = inner + 2.0 * outer;
        assert!((integral / q - 1.0).abs() < 1e-9, "{integral} vs {q}");
        // Slip zone: exactly μ p(x); at the centre, μ p₀ (1 − c/a).
        let x = 0.5 * (t.c + t.a);
        let p_x = t.p0 * (1.0 - (x / t.a).powi(2)).sqrt();
        assert!((t.traction(x) - 0.3 * p_x).abs() < 1e-15);
        assert!((t.traction(0.0) - 0.3 * t.p0 * (1.0 - t.c / t.a)).abs() < 1e-15);
        // A negative Q flips only the sign.
        let neg = Theory::new(&REF, p, -q).unwrap();
        assert_eq!(neg.sign, -1.0);
        assert_eq!(neg.c, t.c);
        // |Q| ≥ μP: no stick zone.
        assert!(Theory::new(&REF, p, 0.3 * p).is_none());
    }

    /// Nodes on Gauss–Chebyshev points of the second kind for the stick ellipse (as the Hertz
    /// moment test): λₙ an arbitrary positive profile, λₜ = μλₙ − s w with w the ellipse's
    /// weights, so that μλₙ − sλₜ is exactly the ellipse of half-width c.
    fn chebyshev_nodes(c: f64, sign: f64) -> Vec<NodeSample> {
        let n = 9;
        (1..=n)
            .map(|i| {
                let th = f64::from(i) * std::f64::consts::PI / f64::from(n + 1);
                let normal = 1.0 + 0.1 * f64::from(i);
                let w = 0.01 * th.sin().powi(2);
                NodeSample {
                    position: [0.4 + c * th.cos(), 0.4],
                    multiplier: normal,
                    pressure: normal,
                    active: true,
                    weight: 1.0,
                    tangential_multiplier: Some(sign * (0.3 * normal - w)),
                    tangential_traction: Some(sign * (0.3 * normal - w)),
                }
            })
            .collect()
    }

    #[test]
    fn the_second_moment_of_mu_lambda_n_minus_lambda_t_gives_c_exactly() {
        // Σ wᵢ sᵢ² / Σ wᵢ = c²/4 exactly on these points (the Hertz moment test's rule), for
        // either sign of the tangential forces.
        for sign in [1.0, -1.0] {
            let nodes = chebyshev_nodes(0.03, sign);
            let t = Theory {
                a: 0.05,
                p0: 1.0,
                c: 0.03,
                mu: 0.3,
                sign,
            };
            let got = stick_half_width(&nodes, [0.4, 0.4], &t).unwrap();
            assert!((got / 0.03 - 1.0).abs() < 1e-13, "sign {sign}: {got}");
        }
    }

    #[test]
    fn the_traction_error_is_zero_on_the_profile_and_relative_off_it() {
        let t = Theory::new(&REF, 1e-3, -1.5e-4).unwrap();
        let h = t.a / 20.0;
        let make = |scale: f64| -> Vec<NodeSample> {
            (-25..=25)
                .map(|i| {
                    let x = f64::from(i) * h;
                    let q = t.sign * scale * t.traction(x.abs());
                    NodeSample {
                        position: [0.4 + x, 0.4],
                        weight: h,
                        tangential_multiplier: Some(q * h),
                        tangential_traction: Some(q),
                        ..NodeSample::default()
                    }
                })
                .collect()
        };
        let exact = traction_error(&make(1.0), [0.4, 0.4], &t).unwrap();
        assert!(exact < 1e-14, "{exact}");
        // 3 % too large everywhere: an rms relative error of exactly 3 %.
        let off = traction_error(&make(1.03), [0.4, 0.4], &t).unwrap();
        assert!((off - 0.03).abs() < 1e-12, "{off}");
        // The wrong sign (traction opposing Q) is an error of 200 %.
        let flipped = Theory { sign: -t.sign, ..t };
        let wrong = traction_error(&make(1.0), [0.4, 0.4], &flipped).unwrap();
        assert!((wrong - 2.0).abs() < 1e-12, "{wrong}");
    }

    #[test]
    fn a_pair_sliding_as_a_whole_or_without_tangential_forces_is_refused() {
        let mut nodes = chebyshev_nodes(0.03, 1.0);
        for n in &mut nodes {
            n.tangential_multiplier = Some(0.31 * n.multiplier);
        }
        let err = theory_of_nodes(&REF, &nodes, 2).unwrap_err();
        assert!(
            matches!(err, AccuracyError::FullSlip { pair: 2, .. }),
            "{err}"
        );
        nodes[0].tangential_multiplier = None;
        let err = theory_of_nodes(&REF, &nodes, 1).unwrap_err();
        assert_eq!(err, AccuracyError::NoTangential { pair: 1 });
    }
}
