//! Finite elements, one file per element: each implements [`Element`] (stiffness, body force,
//! strain at the centre, interpolation weights at a point), and [`of`] is the one place that
//! maps a mesh's [`ElementKind`] to its element.  The material is apart ([`material`]).
//!
//! Local unknowns are interleaved per node: (u₁ₓ, u₁ᵧ, u₂ₓ, u₂ᵧ, …).  Strains are
//! ε = (εₓₓ, εᵧᵧ, γₓᵧ) = B u and stresses σ = (σₓₓ, σᵧᵧ, σₓᵧ) = D ε.
//!
//! Adding an element (P2, say) is one file here implementing [`Element`], one arm in [`of`],
//! and the mesher that makes its cells (docs/architecture.md, "Adding an element").

pub mod material;
pub mod p1;
pub mod q1;

use nalgebra::{DMatrix, SVector};

use crate::geometry::Point;
use crate::mesh::ElementKind;

pub use material::{von_mises, Elasticity, Material};
pub use p1::P1;
pub use q1::Q1;

/// A finite element for plane elasticity: what assembly, loads, stress recovery and probes ask
/// of a cell, given its nodes' coordinates `p` (counter-clockwise, [`Element::nodes`] of them).
pub trait Element: Sync {
    /// The mesh's name for this element.
    fn kind(&self) -> ElementKind;

    /// Nodes per cell.
    fn nodes(&self) -> usize;

    /// Element stiffness (2·nodes square, interleaved unknowns) for elasticity `d` and
    /// out-of-plane `thickness`.
    fn stiffness(&self, p: &[Point], d: &Elasticity, thickness: f64) -> DMatrix<f64>;

    /// Consistent nodal forces (2·nodes, interleaved) of a body force `g` per unit volume.
    fn body_force(&self, p: &[Point], g: [f64; 2], thickness: f64) -> Vec<f64>;

    /// Strain ε = B u at the cell's centre, from the cell's nodal displacements `u`.
    fn centre_strain(&self, p: &[Point], u: &[[f64; 2]]) -> SVector<f64, 3>;

    /// The shape functions' values at `point` when it lies in the cell (within `tol`, a length),
    /// `None` otherwise: the weights that interpolate nodal values there.
    fn weights_at(&self, p: &[Point], point: Point, tol: f64) -> Option<Vec<f64>>;
}

/// The element of a mesh's cells.
pub fn of(kind: ElementKind) -> &'static dyn Element {
    match kind {
        ElementKind::P1 => &P1,
        ElementKind::Q1 => &Q1,
    }
}

/// The first `N` points of a cell (a cell of another element is a caller's bug: it panics on
/// a short slice, as indexing does).
fn corners<const N: usize>(p: &[Point]) -> [Point; N] {
    std::array::from_fn(|i| p[i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Plane;
    use nalgebra::SVector;

    fn material(plane: Plane) -> Material {
        Material {
            young: 2.0,
            poisson: 0.3,
            plane,
        }
    }

    /// The three rigid-body modes (two translations, one rotation) of a set of nodes.
    fn rigid_modes(p: &[Point]) -> Vec<Vec<f64>> {
        let tx = p.iter().flat_map(|_| [1.0, 0.0]).collect();
        let ty = p.iter().flat_map(|_| [0.0, 1.0]).collect();
        let rot = p.iter().flat_map(|q| [-q[1], q[0]]).collect();
        vec![tx, ty, rot]
    }

    #[test]
    fn uniform_strain_gives_d_times_strain() {
        // u = (0.01 x + 0.002 y, −0.003 x + 0.02 y): ε = (0.01, 0.02, −0.001)
        let u = |q: Point| [0.01 * q[0] + 0.002 * q[1], -0.003 * q[0] + 0.02 * q[1]];
        let p = [[0.0, 0.0], [2.0, 0.3], [0.5, 1.0]];
        let (b, _) = p1::strain(p);
        let ue = SVector::<f64, 6>::from_iterator(p.iter().flat_map(|q| u(*q)));
        let eps = b * ue;
        assert!(
            (eps - SVector::<f64, 3>::new(0.01, 0.02, -0.001))
                .abs()
                .max()
                < 1e-15
        );
        let q = [[0.0, 0.0], [1.2, 0.1], [1.0, 0.9], [-0.1, 1.1]];
        let uq = SVector::<f64, 8>::from_iterator(q.iter().flat_map(|x| u(*x)));
        let (bq, _) = q1::strain(q, 0.3, -0.2);
        assert!(
            (bq * uq - SVector::<f64, 3>::new(0.01, 0.02, -0.001))
                .abs()
                .max()
                < 1e-15
        );
    }

    #[test]
    fn plane_strain_matches_lame_form_and_von_mises_of_uniaxial() {
        let m = material(Plane::Strain);
        let d = m.elasticity();
        let (l, mu) = (m.lambda(), m.mu());
        assert!((d[(0, 0)] - (l + 2.0 * mu)).abs() < 1e-14);
        assert!((von_mises([3.0, 0.0, 0.0, 0.0]) - 3.0).abs() < 1e-14);
        assert!((von_mises([0.0, 0.0, 1.0, 0.0]) - 3f64.sqrt()).abs() < 1e-14);
    }

    /// The surface compliance is 1/E′ with E′ the in-plane modulus of a strip free of
    /// transverse stress: σₓₓ = (D₁₁ − D₁₂²/D₂₂) εₓₓ when σᵧᵧ = 0, read here from D itself
    /// (an independent route from `plane_modulus`'s closed forms). Round-off only.
    #[test]
    fn surface_compliance_is_the_inverse_of_the_uniaxial_in_plane_modulus() {
        for plane in [Plane::Strain, Plane::Stress] {
            for poisson in [0.0, 0.3, 0.49] {
                let m = Material {
                    young: 7.0,
                    poisson,
                    plane,
                };
                let d = m.elasticity();
                let uniaxial = d[(0, 0)] - d[(0, 1)] * d[(1, 0)] / d[(1, 1)];
                let c = m.surface_compliance();
                assert!(
                    (c * uniaxial - 1.0).abs() < 1e-14,
                    "{plane:?} ν = {poisson}"
                );
            }
        }
        // plane stress: the surface gives 1/E whatever ν
        let stress = |poisson| Material {
            young: 4.0,
            poisson,
            plane: Plane::Stress,
        };
        assert_eq!(stress(0.1).surface_compliance(), 0.25);
        assert_eq!(stress(0.45).surface_compliance(), 0.25);
    }

    #[test]
    fn body_forces_sum_to_area_times_density() {
        let p = [[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]];
        let f = p1::body_force(p, [0.0, -3.0], 1.0);
        assert!((f.iter().sum::<f64>() + 3.0).abs() < 1e-14);
        let q = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.5], [0.0, 1.5]];
        let fq = q1::body_force(q, [1.0, 0.0], 2.0);
        assert!((fq.iter().sum::<f64>() - 6.0).abs() < 1e-13);
    }

    /// Every element through the trait: a symmetric stiffness, positive semi-definite with
    /// exactly the three rigid modes as kernel (P1 exactly; Q1 with 2×2 Gauss points, no
    /// spurious zero-energy mode), in plane strain and plane stress; weights that sum to one
    /// and reproduce the point (linear completeness); body forces that sum to the force times
    /// the cell's area (the areas computed by hand).  Tolerances: round-off relative to the
    /// largest entry of K.
    #[test]
    fn every_element_is_complete_through_the_trait() {
        let cells: [(ElementKind, Vec<Point>, f64); 2] = [
            // ½|(1.2)(0.7) − (−0.3)(0.3)| = 0.465.
            (
                ElementKind::P1,
                vec![[0.1, 0.2], [1.3, -0.1], [0.4, 0.9]],
                0.465,
            ),
            // Shoelace: ½ Σ (xᵢyᵢ₊₁ − xᵢ₊₁yᵢ) = ½(0 + 0.98 + 1.19 + 0) = 1.085.
            (
                ElementKind::Q1,
                vec![[0.0, 0.0], [1.2, 0.1], [1.0, 0.9], [-0.1, 1.1]],
                1.085,
            ),
        ];
        for (kind, p, area) in cells {
            let e = of(kind);
            assert_eq!(e.kind(), kind);
            assert_eq!(e.nodes(), p.len());
            for plane in [Plane::Strain, Plane::Stress] {
                let k = e.stiffness(&p, &material(plane).elasticity(), 1.0);
                let scale = k.abs().max();
                assert!((&k - k.transpose()).abs().max() < 1e-14 * scale);
                for mode in rigid_modes(&p) {
                    let v = nalgebra::DVector::from_vec(mode);
                    assert!((&k * v).abs().max() < 1e-13 * scale, "{kind:?}");
                }
                let eig = k.symmetric_eigenvalues();
                let zero = eig.iter().filter(|e| e.abs() < 1e-12 * scale).count();
                assert_eq!(zero, 3, "{kind:?} {plane:?}: the kernel is the rigid modes");
                assert!(eig.iter().all(|e| *e > -1e-12 * scale));
            }
            let f = e.body_force(&p, [0.0, -2.0], 1.5);
            assert!(
                (f.iter().sum::<f64>() + 2.0 * 1.5 * area).abs() < 1e-13,
                "{kind:?}"
            );
            let centre = p.iter().fold([0.0, 0.0], |c, q| {
                [c[0] + q[0] / p.len() as f64, c[1] + q[1] / p.len() as f64]
            });
            let w = e
                .weights_at(&p, centre, 1e-12)
                .expect("the centroid is inside");
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            for c in 0..2 {
                let x: f64 = w.iter().zip(&p).map(|(wi, q)| wi * q[c]).sum();
                assert!((x - centre[c]).abs() < 1e-13, "{kind:?}");
            }
            assert!(e.weights_at(&p, [5.0, 5.0], 1e-12).is_none());
        }
    }
}
