//! The bilinear quadrilateral (Q1): four corner nodes, 2×2 Gauss quadrature.

use nalgebra::{DMatrix, SMatrix, SVector};

use super::{corners, Elasticity, Element};
use crate::geometry::Point;
use crate::mesh::ElementKind;

/// The bilinear quadrilateral.
#[derive(Debug, Clone, Copy, Default)]
pub struct Q1;

const GAUSS: f64 = 0.577_350_269_189_625_8; // 1/√3

/// ξ and η of the four corners, counter-clockwise from (−1, −1).
const SX: [f64; 4] = [-1.0, 1.0, 1.0, -1.0];
const SY: [f64; 4] = [-1.0, -1.0, 1.0, 1.0];

/// Strain–displacement matrix and Jacobian determinant of a bilinear quad at (ξ, η).
pub fn strain(p: [Point; 4], xi: f64, eta: f64) -> (SMatrix<f64, 3, 8>, f64) {
    let mut dxi = [0.0; 4];
    let mut deta = [0.0; 4];
    for a in 0..4 {
        dxi[a] = 0.25 * SX[a] * (1.0 + SY[a] * eta);
        deta[a] = 0.25 * SY[a] * (1.0 + SX[a] * xi);
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
pub fn stiffness(p: [Point; 4], d: &Elasticity, thickness: f64) -> SMatrix<f64, 8, 8> {
    let mut k = SMatrix::<f64, 8, 8>::zeros();
    for xi in [-GAUSS, GAUSS] {
        for eta in [-GAUSS, GAUSS] {
            let (b, det) = strain(p, xi, eta);
            k += b.transpose() * d * b * (det * thickness);
        }
    }
    k
}

/// Consistent nodal forces of a body force `g` (per unit area) on a bilinear quad.
pub fn body_force(p: [Point; 4], g: [f64; 2], thickness: f64) -> SVector<f64, 8> {
    let mut f = SVector::<f64, 8>::zeros();
    for xi in [-GAUSS, GAUSS] {
        for eta in [-GAUSS, GAUSS] {
            let (_, det) = strain(p, xi, eta);
            for a in 0..4 {
                let n = 0.25 * (1.0 + SX[a] * xi) * (1.0 + SY[a] * eta);
                f[2 * a] += n * g[0] * det * thickness;
                f[2 * a + 1] += n * g[1] * det * thickness;
            }
        }
    }
    f
}

/// The four shape functions at (ξ, η).
fn shape(xi: f64, eta: f64) -> [f64; 4] {
    [
        0.25 * (1.0 - xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 + eta),
        0.25 * (1.0 - xi) * (1.0 + eta),
    ]
}

/// Local coordinates (ξ, η) of a point in a bilinear quad, by Newton's method.
fn local(p: [Point; 4], x: Point) -> Option<(f64, f64)> {
    let (mut xi, mut eta) = (0.0_f64, 0.0_f64);
    for _ in 0..30 {
        let n = shape(xi, eta);
        let dxi = [
            -0.25 * (1.0 - eta),
            0.25 * (1.0 - eta),
            0.25 * (1.0 + eta),
            -0.25 * (1.0 + eta),
        ];
        let deta = [
            -0.25 * (1.0 - xi),
            -0.25 * (1.0 + xi),
            0.25 * (1.0 + xi),
            0.25 * (1.0 - xi),
        ];
        let (mut fx, mut fy, mut j11, mut j12, mut j21, mut j22) =
            (-x[0], -x[1], 0.0, 0.0, 0.0, 0.0);
        for a in 0..4 {
            fx += n[a] * p[a][0];
            fy += n[a] * p[a][1];
            j11 += dxi[a] * p[a][0];
            j12 += deta[a] * p[a][0];
            j21 += dxi[a] * p[a][1];
            j22 += deta[a] * p[a][1];
        }
        let det = j11 * j22 - j12 * j21;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let dx = (j22 * fx - j12 * fy) / det;
        let dy = (-j21 * fx + j11 * fy) / det;
        xi -= dx;
        eta -= dy;
        if dx.abs() + dy.abs() < 1e-14 {
            break;
        }
    }
    (xi.is_finite() && eta.is_finite()).then_some((xi, eta))
}

impl Element for Q1 {
    fn kind(&self) -> ElementKind {
        ElementKind::Q1
    }

    fn nodes(&self) -> usize {
        4
    }

    fn stiffness(&self, p: &[Point], d: &Elasticity, thickness: f64) -> DMatrix<f64> {
        let k = stiffness(corners(p), d, thickness);
        DMatrix::from_column_slice(8, 8, k.as_slice())
    }

    fn body_force(&self, p: &[Point], g: [f64; 2], thickness: f64) -> Vec<f64> {
        body_force(corners(p), g, thickness)
            .iter()
            .copied()
            .collect()
    }

    fn centre_strain(&self, p: &[Point], u: &[[f64; 2]]) -> SVector<f64, 3> {
        let (b, _) = strain(corners(p), 0.0, 0.0);
        b * SVector::<f64, 8>::from_iterator(u.iter().flatten().copied())
    }

    /// The shape functions at the point's local coordinates (found by Newton's method),
    /// accepted when |ξ|, |η| ≤ 1 + 10⁻⁹ (`tol` is not used: the test is in local coordinates).
    fn weights_at(&self, p: &[Point], point: Point, _tol: f64) -> Option<Vec<f64>> {
        let (xi, eta) = local(corners(p), point)?;
        let eps = 1e-9;
        if xi.abs() > 1.0 + eps || eta.abs() > 1.0 + eps {
            return None;
        }
        Some(shape(xi, eta).to_vec())
    }
}
