//! Discretisation error of a run against the scene's analytic answer (`[reference]`).
//!
//! The reference values come from formulas written in the scene (Johnson's Hertz line contact,
//! the patch test's uniform pressure), never from a finer solve.  Every error is relative and
//! signed, `computed / reference − 1`; studies plot its absolute value.
//!
//! # What is measured, and why this way
//!
//! The inputs are the reference pair's slave nodes as `result.json` reports them: position
//! (undeformed), multiplier λⱼ (the nodal contact force, per unit thickness) and pressure pⱼ
//! (λⱼ divided by the node's weight: the tributary length for node-to-segment, Dⱼⱼ = ∫Nⱼ for
//! mortar), and whether the row counts as in contact.  `d` is the distance from the reference
//! `centre` to the node, measured along the straight line (a chord): on a flat slave side that
//! is the distance along the interface; on a circular side of radius R it is short of the arc
//! length by s³/(24R²), a relative 1.0 × 10⁻⁴ at s = a = 0.05, R = 1 (the Hertz fixture).
//!
//! **Half-width a, from the second moment of the nodal forces.**  For the Hertz pressure
//! p(s) = p₀√(1 − s²/a²),
//!
//! ```text
//! ∫ s² p ds / ∫ p ds = (π a³ p₀ / 8) / (π a p₀ / 2) = a² / 4,   so   a = 2 √(Σ λⱼ dⱼ² / Σ λⱼ).
//! ```
//!
//! The nodal forces are λⱼ ≈ ∫ Nⱼ p ds, so Σ λⱼ dⱼ² = ∫ p · I_h(s²) ds with I_h the piecewise
//! linear interpolant; I_h(s²) − s² = (s − sᵢ)(sᵢ₊₁ − s) ≥ 0 on each segment, whose mean is
//! h²/6: the estimator reads a²/4 + h²/6, a bias a_h/a − 1 ≈ (1/3)(h/a)² on a uniform
//! interface mesh (0.08 % at a/h = 20, 0.33 % at a/h = 10), below the discretisation error
//! itself and falling with it.  It uses every node, so no single node (nor where exactly the contact
//! ends, which a mesh locates only to ±h) decides it, and it needs the forces only: the same
//! estimator for both formulations whatever their weights.  (Both formulations' multipliers act
//! along the master's normals; on a curved master they are tilted by θ ≤ a/R in the contact
//! zone, so they weigh the edge nodes by up to 1/cos θ − 1 ≈ (a/R)²/2 more than the vertical
//! load does: a term of the order Hertz's own theory neglects.)  The "active extent" (half the span
//! of the nodes in contact) is first-order, ±h.
//!
//! **Peak pressure p₀, from an elliptical fit of the inner half.**  p² = p₀² − (p₀²/a²) s² is
//! linear in s², so a least-squares line through (dⱼ², pⱼ²) over the nodes in contact with
//! dⱼ ≤ a_m / 2 (a_m the moment half-width above, not the reference) gives p₀ as the square root
//! of its intercept.  The inner half is where the exact pressure is smooth (|p''| ≤ 1.54 p₀/a²
//! there, while at the edges p has a square-root singularity that the mesh smears over one
//! element), and averaging over the a/h nodes there keeps one node's error (a mesh vertex of
//! the polygonal arc, a non-matching master node) from deciding the figure.  The plain maximum
//! nodal pressure is reported beside it (`peak_nodal_pressure`): it is what a user reads off the
//! pressure plot, but it is pointwise (first order where the field oscillates) and it misses p₀
//! by up to p₀ h²/(8a²) when no node sits at the centre.  With fewer than two distinct dⱼ in the
//! inner half (a/h below ~2) the fit falls back to the maximum.
//!
//! **Patch test.**  The largest |pⱼ / p − 1| over the slave nodes whose row is in contact.
//!
//! **Cattaneo–Mindlin partial slip.**  The stick half-width c and the tangential traction
//! profile, against Cattaneo's formulas for the pair's own forces; see [`cattaneo`].  The
//! Hertz half-width and peak pressure above are measured too, against a = √(4PR/(πE*)) and
//! p₀ = 2P/(πa) for the run's normal force P.

use crate::geometry::Point;
use crate::report::{ContactNodeReport, RunReport};
use crate::scene::Reference;

pub mod cattaneo;

/// One slave node, as the estimators need it (built from a [`ContactNodeReport`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NodeSample {
    /// Undeformed position.
    pub position: Point,
    /// Contact force λ (per unit thickness).
    pub multiplier: f64,
    /// Pressure λ / weight.
    pub pressure: f64,
    /// Whether the row counts as in contact.
    pub active: bool,
    /// The length λ is divided by to give the pressure (the report's `weight`).
    pub weight: f64,
    /// Frictional pairs: the tangential force λₜ along the row's tangent.
    pub tangential_multiplier: Option<f64>,
    /// Frictional pairs: λₜ / weight.
    pub tangential_traction: Option<f64>,
}

impl From<&ContactNodeReport> for NodeSample {
    fn from(n: &ContactNodeReport) -> Self {
        Self {
            position: [n.x, n.y],
            multiplier: n.multiplier,
            pressure: n.pressure,
            active: n.active,
            weight: n.weight,
            tangential_multiplier: n.tangential_multiplier,
            tangential_traction: n.tangential_traction,
        }
    }
}

/// A computed value next to its reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// From the run.
    pub computed: f64,
    /// From the scene's `[reference]`.
    pub reference: f64,
}

impl Estimate {
    /// Signed relative error `computed / reference − 1`.
    pub fn error(&self) -> f64 {
        self.computed / self.reference - 1.0
    }
}

/// The errors of one run against the scene's reference (each `None` when the reference does not
/// state that value).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Accuracy {
    /// Hertz half-width a, from the second moment of the nodal forces.
    pub half_width: Option<Estimate>,
    /// Hertz peak pressure p₀, from the elliptical fit of the inner half.
    pub peak_pressure: Option<Estimate>,
    /// Hertz peak pressure p₀ against the largest nodal pressure.
    pub peak_nodal_pressure: Option<Estimate>,
    /// Patch test: the largest |pⱼ / p − 1| over the nodes in contact.
    pub pressure_deviation: Option<f64>,
    /// Cattaneo–Mindlin: the stick half-width c, from the second moment of μλₙ − λₜ.
    pub stick_half_width: Option<Estimate>,
    /// Cattaneo–Mindlin: the rms relative error of the tangential traction profile over the
    /// contact zone (see [`cattaneo::traction_error`]).
    pub tangential_traction: Option<f64>,
}

/// Why the errors cannot be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AccuracyError {
    /// The report has no such pair.
    #[error("[reference] pair = {pair}: the run reports {pairs} contact pair(s)")]
    NoPair {
        /// 1-based pair of the reference.
        pair: usize,
        /// Pairs in the report.
        pairs: usize,
    },
    /// A Cattaneo–Mindlin reference on a pair whose report carries no tangential forces.
    #[error("contact pair {pair} reports no tangential forces: a Cattaneo–Mindlin [reference] needs a frictional pair")]
    NoTangential {
        /// 1-based pair.
        pair: usize,
    },
    /// |Q| ≥ μP: the whole zone slides, there is no stick zone.
    #[error("contact pair {pair} slides as a whole (|Q| / μP = {ratio:.4} ≥ 1): Cattaneo–Mindlin partial slip needs |Q| < μP")]
    FullSlip {
        /// 1-based pair.
        pair: usize,
        /// |Q| / (μ P).
        ratio: f64,
    },
    /// No force crosses the pair, so there is no pressure to compare.
    #[error("contact pair {pair} transmits no force (no multiplier is positive): nothing to compare with [reference]")]
    NoContact {
        /// 1-based pair.
        pair: usize,
    },
}

/// `a = 2 √(Σ λⱼ dⱼ² / Σ λⱼ)` over the nodes (negative round-off multipliers count as 0); `None`
/// when no multiplier is positive.  See the [module docs](self).
pub fn moment_half_width(nodes: &[NodeSample], centre: Point) -> Option<f64> {
    let (mut force, mut moment) = (0.0, 0.0);
    for n in nodes {
        let l = n.multiplier.max(0.0);
        let d = crate::geometry::distance(n.position, centre);
        force += l;
        moment += l * d * d;
    }
    (force > 0.0 && force.is_finite()).then(|| 2.0 * (moment / force).sqrt())
}

/// The largest pressure over the nodes in contact (`None` when none is).
pub fn max_pressure(nodes: &[NodeSample]) -> Option<f64> {
    nodes
        .iter()
        .filter(|n| n.active)
        .map(|n| n.pressure)
        .fold(None, |m: Option<f64>, p| Some(m.map_or(p, |m| m.max(p))))
}

/// p₀ from the least-squares line p² = α − β d² through the nodes in contact with
/// d ≤ `window` (p₀ = √α), or the largest nodal pressure when fewer than two distinct d² lie
/// in the window.  See the [module docs](self).
pub fn fitted_peak_pressure(nodes: &[NodeSample], centre: Point, window: f64) -> Option<f64> {
    let pts: Vec<(f64, f64)> = nodes
        .iter()
        .filter(|n| n.active)
        .filter_map(|n| {
            let d = crate::geometry::distance(n.position, centre);
            (d <= window).then_some((d * d, n.pressure * n.pressure))
        })
        .collect();
    let m = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / m;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / m;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    // Distinct abscissae: the spread must exceed round-off of the squared distances.
    let spread = pts.iter().map(|p| p.0).fold(0.0, f64::max);
    if pts.len() >= 2 && sxx > (1e-12 * spread).powi(2) * m {
        let alpha = my - sxy / sxx * mx;
        if alpha > 0.0 {
            return Some(alpha.sqrt());
        }
    }
    max_pressure(nodes)
}

/// The largest |pⱼ / p − 1| over the nodes in contact (`None` when none is).
pub fn pressure_deviation(nodes: &[NodeSample], pressure: f64) -> Option<f64> {
    nodes
        .iter()
        .filter(|n| n.active)
        .map(|n| (n.pressure / pressure - 1.0).abs())
        .fold(None, |m: Option<f64>, e| Some(m.map_or(e, |m| m.max(e))))
}

/// The errors of `nodes` (one pair's slave nodes) against `reference` (see the
/// [module docs](self)).  The centre of the fit is `reference.centre`, or the force centroid
/// Σλⱼxⱼ / Σλⱼ when the reference names none.
pub fn accuracy_of_nodes(
    reference: &Reference,
    nodes: &[NodeSample],
) -> Result<Accuracy, AccuracyError> {
    let pair = reference.pair + 1;
    let force: f64 = nodes.iter().map(|n| n.multiplier.max(0.0)).sum();
    if !(force > 0.0 && force.is_finite()) {
        return Err(AccuracyError::NoContact { pair });
    }
    let centre = reference.centre.unwrap_or_else(|| {
        let mut c = [0.0, 0.0];
        for n in nodes {
            let l = n.multiplier.max(0.0);
            c[0] += l * n.position[0] / force;
            c[1] += l * n.position[1] / force;
        }
        c
    });
    let a_m = moment_half_width(nodes, centre);
    let mut out = Accuracy::default();
    let (mut half_width, mut peak_pressure) = (reference.half_width, reference.peak_pressure);
    if let Some(c) = &reference.cattaneo {
        let theory = cattaneo::theory_of_nodes(c, nodes, pair)?;
        half_width = Some(theory.a);
        peak_pressure = Some(theory.p0);
        out.stick_half_width =
            cattaneo::stick_half_width(nodes, centre, &theory).map(|computed| Estimate {
                computed,
                reference: theory.c,
            });
        out.tangential_traction = cattaneo::traction_error(nodes, centre, &theory);
    }
    if let (Some(reference), Some(computed)) = (half_width, a_m) {
        out.half_width = Some(Estimate {
            computed,
            reference,
        });
    }
    if let Some(p0) = peak_pressure {
        let window = 0.5 * a_m.unwrap_or(0.0);
        out.peak_pressure = fitted_peak_pressure(nodes, centre, window).map(|computed| Estimate {
            computed,
            reference: p0,
        });
        out.peak_nodal_pressure = max_pressure(nodes).map(|computed| Estimate {
            computed,
            reference: p0,
        });
    }
    if let Some(p) = reference.pressure {
        out.pressure_deviation = pressure_deviation(nodes, p);
    }
    Ok(out)
}

/// The errors of a run (its `result.json` content) against the scene's reference.
pub fn accuracy(reference: &Reference, report: &RunReport) -> Result<Accuracy, AccuracyError> {
    let contact = report
        .contacts
        .get(reference.pair)
        .ok_or(AccuracyError::NoPair {
            pair: reference.pair + 1,
            pairs: report.contacts.len(),
        })?;
    let nodes: Vec<NodeSample> = contact.nodes.iter().map(NodeSample::from).collect();
    accuracy_of_nodes(reference, &nodes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference() -> Reference {
        Reference {
            pair: 0,
            centre: Some([0.4, 0.4]),
            half_width: Some(0.05),
            peak_pressure: Some(0.0137),
            pressure: None,
            cattaneo: None,
        }
    }

    /// Nodes at s = centre + k h along x, carrying λ = ∫Nⱼ p ds of a given pressure p(s)
    /// (64-panel Simpson on each half-hat: the square-root edges of the ellipse limit it to a
    /// relative ~1e-4 of the edge nodes' forces), and the pressure λ / ∫Nⱼ.
    fn nodes_for(p: impl Fn(f64) -> f64, h: f64, k: i32) -> Vec<NodeSample> {
        (-k..=k)
            .map(|i| {
                let s = f64::from(i) * h;
                let side = |a: f64, b: f64, w: &dyn Fn(f64) -> f64| {
                    let n = 64;
                    let dx = (b - a) / f64::from(n);
                    (0..=n)
                        .map(|j| {
                            let x = a + f64::from(j) * dx;
                            let c = if j == 0 || j == n {
                                1.0
                            } else if j % 2 == 1 {
                                4.0
                            } else {
                                2.0
                            };
                            c * w(x) * p(x)
                        })
                        .sum::<f64>()
                        * dx
                        / 3.0
                };
                let l =
                    side(s - h, s, &|x| (x - (s - h)) / h) + side(s, s + h, &|x| (s + h - x) / h);
                NodeSample {
                    position: [0.4 + s, 0.4],
                    multiplier: l,
                    pressure: l / h,
                    active: l > 0.0,
                    ..NodeSample::default()
                }
            })
            .collect()
    }

    #[test]
    fn the_second_moment_of_point_forces_on_the_ellipse_gives_a_exactly() {
        // Point forces equal to the exact ellipse's forces at its Gauss–Chebyshev points of the
        // second kind: Σ wᵢ sᵢ² / Σ wᵢ = a²/4 exactly for n ≥ 2 (the rule integrates
        // √(1 − t²)·t² exactly), so the estimator must return a to round-off.
        let a = 0.05;
        let n = 7;
        let nodes: Vec<NodeSample> = (1..=n)
            .map(|i| {
                let th = f64::from(i) * std::f64::consts::PI / f64::from(n + 1);
                let w = th.sin().powi(2);
                NodeSample {
                    position: [0.4 + a * th.cos(), 0.4],
                    multiplier: w,
                    pressure: 1.0,
                    active: true,
                    ..NodeSample::default()
                }
            })
            .collect();
        let got = moment_half_width(&nodes, [0.4, 0.4]).unwrap();
        assert!((got / a - 1.0).abs() < 1e-14, "{got}");
    }

    #[test]
    fn the_moment_bias_on_a_uniform_mesh_is_a_third_of_h_over_a_squared() {
        // Nodal forces λⱼ = ∫Nⱼ p of the exact ellipse: Σλⱼ sⱼ² = ∫ p I_h(s²), biased by
        // ∫ p (s − sᵢ)(sᵢ₊₁ − s) ≈ (h²/6) ∫ p, so a_h = 2√(a²/4 + h²/6) and
        // a_h/a − 1 ≈ (1/3)(h/a)² (module docs).  The
        // quadrature of the nodal forces is not exact at the square-root edges, so the check is
        // to 15 % of the predicted bias, which is 4 × 10⁻⁵ absolute here.
        let a = 0.05;
        for ratio in [10.0, 20.0] {
            let h = a / ratio;
            let ellipse = |s: f64| (1.0 - (s / a).powi(2)).max(0.0).sqrt();
            let nodes = nodes_for(ellipse, h, ratio as i32 + 2);
            let got = moment_half_width(&nodes, [0.4, 0.4]).unwrap() / a - 1.0;
            let predicted = (1.0 + 2.0 / 3.0 / (ratio * ratio)).sqrt() - 1.0;
            assert!(
                (got - predicted).abs() <= 0.15 * predicted,
                "a/h = {ratio}: bias {got:e}, predicted {predicted:e}"
            );
        }
    }

    #[test]
    fn the_fit_recovers_p0_from_exact_nodal_pressures_and_ignores_the_edges() {
        // Exact ellipse values at the nodes: p² is exactly linear in d², so the fit returns p₀
        // to round-off whatever the window; corrupting the nodes outside the window changes
        // nothing, corrupting one inside moves the fit by less than the corruption.
        let (a, p0) = (0.05, 0.0137);
        let h = a / 10.0;
        let mut nodes: Vec<NodeSample> = (-12..=12)
            .map(|i| {
                let s = f64::from(i) * h;
                let p = p0 * (1.0 - (s / a).powi(2)).max(0.0).sqrt();
                NodeSample {
                    position: [0.4 + s, 0.4],
                    multiplier: p * h,
                    pressure: p,
                    active: p > 0.0,
                    ..NodeSample::default()
                }
            })
            .collect();
        let got = fitted_peak_pressure(&nodes, [0.4, 0.4], 0.5 * a).unwrap();
        assert!((got / p0 - 1.0).abs() < 1e-12, "{got}");
        // Nodes beyond a/2 (|i| ≥ 6) do not count.
        nodes[12 + 8].pressure *= 1.5;
        nodes[12 - 7].pressure *= 0.5;
        let got = fitted_peak_pressure(&nodes, [0.4, 0.4], 0.5 * a).unwrap();
        assert!((got / p0 - 1.0).abs() < 1e-12, "{got}");
        // The centre node +10 %: the maximum sees all of it, the fit over 11 nodes a fraction.
        nodes[12].pressure *= 1.1;
        let fit = fitted_peak_pressure(&nodes, [0.4, 0.4], 0.5 * a).unwrap() / p0 - 1.0;
        let max = max_pressure(&nodes).unwrap() / p0 - 1.0;
        assert!((max - 0.1).abs() < 1e-12);
        assert!(fit > 0.0 && fit < 0.05, "{fit}");
    }

    #[test]
    fn few_nodes_in_the_window_fall_back_to_the_maximum() {
        let nodes = [
            NodeSample {
                position: [0.4, 0.4],
                multiplier: 1.0,
                pressure: 2.0,
                active: true,
                ..NodeSample::default()
            },
            NodeSample {
                position: [0.5, 0.4],
                multiplier: 1.0,
                pressure: 3.0,
                active: true,
                ..NodeSample::default()
            },
        ];
        assert_eq!(fitted_peak_pressure(&nodes, [0.4, 0.4], 0.05), Some(3.0));
    }

    #[test]
    fn the_patch_deviation_is_the_worst_active_node() {
        let node = |p: f64, active: bool| NodeSample {
            position: [0.0, 0.0],
            multiplier: p,
            pressure: p,
            active,
            ..NodeSample::default()
        };
        let nodes = [
            node(2.0, true),
            node(2.2, true),
            node(1.9, true),
            node(0.0, false),
        ];
        let got = pressure_deviation(&nodes, 2.0).unwrap();
        assert!((got - 0.1).abs() < 1e-15, "{got}");
        let r = Reference {
            pair: 0,
            centre: None,
            half_width: None,
            peak_pressure: None,
            pressure: Some(2.0),
            cattaneo: None,
        };
        let acc = accuracy_of_nodes(&r, &nodes).unwrap();
        assert_eq!(acc.pressure_deviation, Some(got));
        assert_eq!(acc.half_width, None);
        assert_eq!(acc.peak_pressure, None);
    }

    #[test]
    fn hertz_errors_are_signed_and_relative() {
        // A scaled ellipse: a 2 % wider zone at the same total force has p₀ 2 % lower
        // (p₀ = 2P/(πa)); the point-force rule of the first test gives a exactly, and nodal
        // pressures on the ellipse make the fit exact, so both errors are known exactly.
        let (a, p0) = (0.05 * 1.02, 0.0137 / 1.02);
        let n = 21;
        let nodes: Vec<NodeSample> = (1..=n)
            .map(|i| {
                let th = f64::from(i) * std::f64::consts::PI / f64::from(n + 1);
                NodeSample {
                    position: [0.4 + a * th.cos(), 0.4],
                    multiplier: th.sin().powi(2),
                    pressure: p0 * th.sin(),
                    active: true,
                    ..NodeSample::default()
                }
            })
            .collect();
        let acc = accuracy_of_nodes(&reference(), &nodes).unwrap();
        let ea = acc.half_width.unwrap().error();
        let ep = acc.peak_pressure.unwrap().error();
        assert!((ea - 0.02).abs() < 1e-12, "{ea}");
        assert!((ep - (1.0 / 1.02 - 1.0)).abs() < 1e-12, "{ep}");
        assert!(acc.peak_nodal_pressure.unwrap().error() <= 0.0);
    }

    #[test]
    fn nothing_in_contact_is_an_error_naming_the_pair() {
        let nodes = [NodeSample {
            position: [0.0, 0.0],
            multiplier: 0.0,
            pressure: 0.0,
            active: false,
            ..NodeSample::default()
        }];
        let err = accuracy_of_nodes(&reference(), &nodes).unwrap_err();
        assert_eq!(err, AccuracyError::NoContact { pair: 1 });
        assert!(err.to_string().contains("pair 1"));
    }
}
