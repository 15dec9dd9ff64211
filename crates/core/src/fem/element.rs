//! Element matrices of P1 triangles and Q1 quadrilaterals (2×2 Gauss), and the elasticity
//! matrix for plane strain or plane stress.
//!
//! Local unknowns are interleaved per node: (u₁ₓ, u₁ᵧ, u₂ₓ, u₂ᵧ, …).  Strains are
//! ε = (εₓₓ, εᵧᵧ, γₓᵧ) = B u and stresses σ = (σₓₓ, σᵧᵧ, σₓᵧ) = D ε.

use nalgebra::{SMatrix, SVector};

use crate::geometry::Point;
use crate::scene::Plane;

/// The 3×3 elasticity matrix D.
pub type Elasticity = SMatrix<f64, 3, 3>;

/// An isotropic linear-elastic material under a plane idealisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus E.
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Plane strain or plane stress.
    pub plane: Plane,
}

impl Material {
    /// Lamé's first parameter λ = Eν / ((1+ν)(1−2ν)).
    pub fn lambda(&self) -> f64 {
        let (e, nu) = (self.young, self.poisson);
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    }

    /// Shear modulus μ = E / (2(1+ν)).
    pub fn mu(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }

    /// D such that σ = D ε (plane strain: [[λ+2μ, λ, 0], [λ, λ+2μ, 0], [0, 0, μ]];
    /// plane stress: E/(1−ν²) [[1, ν, 0], [ν, 1, 0], [0, 0, (1−ν)/2]]).
    pub fn elasticity(&self) -> Elasticity {
        match self.plane {
            Plane::Strain => {
                let (l, m) = (self.lambda(), self.mu());
                Elasticity::new(l + 2.0 * m, l, 0.0, l, l + 2.0 * m, 0.0, 0.0, 0.0, m)
            }
            Plane::Stress => {
                let (e, nu) = (self.young, self.poisson);
                let c = e / (1.0 - nu * nu);
                Elasticity::new(
                    c,
                    c * nu,
                    0.0,
                    c * nu,
                    c,
                    0.0,
                    0.0,
                    0.0,
                    c * (1.0 - nu) / 2.0,
                )
            }
        }
    }

    /// Out-of-plane stress σ_zz for in-plane stresses: ν(σₓₓ + σᵧᵧ) in plane strain, 0 in plane
    /// stress.
    pub fn sigma_zz(&self, sxx: f64, syy: f64) -> f64 {
        match self.plane {
            Plane::Strain => self.poisson * (sxx + syy),
            Plane::Stress => 0.0,
        }
    }
}

/// Von Mises equivalent stress of (σₓₓ, σᵧᵧ, σₓᵧ, σ_zz).
pub fn von_mises(s: [f64; 4]) -> f64 {
    let [sxx, syy, sxy, szz] = s;
    (0.5 * ((sxx - syy).powi(2) + (syy - szz).powi(2) + (szz - sxx).powi(2)) + 3.0 * sxy * sxy)
        .sqrt()
}

/// Strain–displacement matrix of a linear triangle and its area.
pub fn p1_strain(p: [Point; 3]) -> (SMatrix<f64, 3, 6>, f64) {
    let twice_area =
        (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
    let mut b = SMatrix::<f64, 3, 6>::zeros();
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let dx = (p[j][1] - p[k][1]) / twice_area;
        let dy = (p[k][0] - p[j][0]) / twice_area;
        b[(0, 2 * i)] = dx;
        b[(1, 2 * i + 1)] = dy;
        b[(2, 2 * i)] = dy;
        b[(2, 2 * i + 1)] = dx;
    }
    (b, 0.5 * twice_area)
}

/// Stiffness of a linear triangle: t · area · Bᵀ D B.
pub fn p1_stiffness(p: [Point; 3], d: &Elasticity, thickness: f64) -> SMatrix<f64, 6, 6> {
    let (b, area) = p1_strain(p);
    b.transpose() * d * b * (area * thickness)
}

const GAUSS: f64 = 0.577_350_269_189_625_8; // 1/√3

/// Strain–displacement matrix and Jacobian determinant of a bilinear quad at (ξ, η).
pub fn q1_strain(p: [Point; 4], xi: f64, eta: f64) -> (SMatrix<f64, 3, 8>, f64) {
    let sx = [-1.0, 1.0, 1.0, -1.0];
    let sy = [-1.0, -1.0, 1.0, 1.0];
    let mut dxi = [0.0; 4];
    let mut deta = [0.0; 4];
    for a in 0..4 {
        dxi[a] = 0.25 * sx[a] * (1.0 + sy[a] * eta);
        deta[a] = 0.25 * sy[a] * (1.0 + sx[a] * xi);
    }
    let (mut j11, mut j12, mut j21, mut j22) = (0.0, 0.0, 0.0, 0.0);
    for a in 0..4 {
        j11 += dxi[a] * p[a][0];
        j12 += dxi[a] * p[a][1];
        j21 += deta[a] * p[a][0];
        j22 += deta[a] * p[a][1];
    }
    let det = j11 * j22 - j12 * j21;
    let mut b = SMatrix::<f64, 3, 8>::zeros();
    for a in 0..4 {
        let dx = (j22 * dxi[a] - j12 * deta[a]) / det;
        let dy = (-j21 * dxi[a] + j11 * deta[a]) / det;
        b[(0, 2 * a)] = dx;
        b[(1, 2 * a + 1)] = dy;
        b[(2, 2 * a)] = dy;
        b[(2, 2 * a + 1)] = dx;
    }
    (b, det)
}

/// Stiffness of a bilinear quad by 2×2 Gauss quadrature.
pub fn q1_stiffness(p: [Point; 4], d: &Elasticity, thickness: f64) -> SMatrix<f64, 8, 8> {
    let mut k = SMatrix::<f64, 8, 8>::zeros();
    for xi in [-GAUSS, GAUSS] {
        for eta in [-GAUSS, GAUSS] {
            let (b, det) = q1_strain(p, xi, eta);
            k += b.transpose() * d * b * (det * thickness);
        }
    }
    k
}

/// Consistent nodal forces of a body force `g` (per unit area) on a triangle: area/3 each.
pub fn p1_body_force(p: [Point; 3], g: [f64; 2], thickness: f64) -> SVector<f64, 6> {
    let (_, area) = p1_strain(p);
    let w = area * thickness / 3.0;
    SVector::<f64, 6>::from_fn(|i, _| w * g[i % 2])
}

/// Consistent nodal forces of a body force `g` (per unit area) on a bilinear quad.
pub fn q1_body_force(p: [Point; 4], g: [f64; 2], thickness: f64) -> SVector<f64, 8> {
    let sx = [-1.0, 1.0, 1.0, -1.0];
    let sy = [-1.0, -1.0, 1.0, 1.0];
    let mut f = SVector::<f64, 8>::zeros();
    for xi in [-GAUSS, GAUSS] {
        for eta in [-GAUSS, GAUSS] {
            let (_, det) = q1_strain(p, xi, eta);
            for a in 0..4 {
                let n = 0.25 * (1.0 + sx[a] * xi) * (1.0 + sy[a] * eta);
                f[2 * a] += n * g[0] * det * thickness;
                f[2 * a + 1] += n * g[1] * det * thickness;
            }
        }
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn p1_rigid_modes_are_in_the_null_space_and_k_is_spd_on_the_rest() {
        let p = [[0.1, 0.2], [1.3, -0.1], [0.4, 0.9]];
        for plane in [Plane::Strain, Plane::Stress] {
            let k = p1_stiffness(p, &material(plane).elasticity(), 1.0);
            assert!((k - k.transpose()).abs().max() < 1e-14);
            for mode in rigid_modes(&p) {
                let v = SVector::<f64, 6>::from_column_slice(&mode);
                assert!((k * v).abs().max() < 1e-13 * k.abs().max());
            }
            let eig = k.symmetric_eigenvalues();
            let zero = eig
                .iter()
                .filter(|e| e.abs() < 1e-12 * k.abs().max())
                .count();
            assert_eq!(zero, 3);
            assert!(eig.iter().all(|e| *e > -1e-12));
        }
    }

    #[test]
    fn q1_rigid_modes_and_rank() {
        let p = [[0.0, 0.0], [1.2, 0.1], [1.0, 0.9], [-0.1, 1.1]];
        let k = q1_stiffness(p, &material(Plane::Strain).elasticity(), 1.0);
        assert!((k - k.transpose()).abs().max() < 1e-14);
        for mode in rigid_modes(&p) {
            let v = SVector::<f64, 8>::from_column_slice(&mode);
            assert!((k * v).abs().max() < 1e-13 * k.abs().max());
        }
        let eig = k.symmetric_eigenvalues();
        let zero = eig
            .iter()
            .filter(|e| e.abs() < 1e-12 * k.abs().max())
            .count();
        assert_eq!(
            zero, 3,
            "2×2 Gauss Q1 has exactly the rigid modes as kernel"
        );
    }

    #[test]
    fn uniform_strain_gives_d_times_strain() {
        // u = (0.01 x + 0.002 y, −0.003 x + 0.02 y): ε = (0.01, 0.02, −0.001)
        let u = |q: Point| [0.01 * q[0] + 0.002 * q[1], -0.003 * q[0] + 0.02 * q[1]];
        let p = [[0.0, 0.0], [2.0, 0.3], [0.5, 1.0]];
        let (b, _) = p1_strain(p);
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
        let (bq, _) = q1_strain(q, 0.3, -0.2);
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

    #[test]
    fn body_forces_sum_to_area_times_density() {
        let p = [[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]];
        let f = p1_body_force(p, [0.0, -3.0], 1.0);
        assert!((f.iter().sum::<f64>() + 3.0).abs() < 1e-14);
        let q = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.5], [0.0, 1.5]];
        let fq = q1_body_force(q, [1.0, 0.0], 2.0);
        assert!((fq.iter().sum::<f64>() - 6.0).abs() < 1e-13);
    }
}
