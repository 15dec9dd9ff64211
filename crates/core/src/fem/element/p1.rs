//! The linear triangle (P1): three corner nodes, constant strain.

use nalgebra::{DMatrix, SMatrix, SVector};

use super::{corners, Elasticity, Element};
use crate::geometry::{self, Point};
use crate::mesh::ElementKind;

/// The linear triangle.
#[derive(Debug, Clone, Copy, Default)]
pub struct P1;

/// Strain–displacement matrix of a linear triangle and its area.
pub fn strain(p: [Point; 3]) -> (SMatrix<f64, 3, 6>, f64) {
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
pub fn stiffness(p: [Point; 3], d: &Elasticity, thickness: f64) -> SMatrix<f64, 6, 6> {
    let (b, area) = strain(p);
    b.transpose() * d * b * (area * thickness)
}

/// Consistent nodal forces of a body force `g` (per unit area) on a triangle: area/3 each.
pub fn body_force(p: [Point; 3], g: [f64; 2], thickness: f64) -> SVector<f64, 6> {
    let (_, area) = strain(p);
    let w = area * thickness / 3.0;
    SVector::<f64, 6>::from_fn(|i, _| w * g[i % 2])
}

impl Element for P1 {
    fn kind(&self) -> ElementKind {
        ElementKind::P1
    }

    fn nodes(&self) -> usize {
        3
    }

    fn stiffness(&self, p: &[Point], d: &Elasticity, thickness: f64) -> DMatrix<f64> {
        let k = stiffness(corners(p), d, thickness);
        DMatrix::from_column_slice(6, 6, k.as_slice())
    }

    fn body_force(&self, p: &[Point], g: [f64; 2], thickness: f64) -> Vec<f64> {
        body_force(corners(p), g, thickness)
            .iter()
            .copied()
            .collect()
    }

    fn centre_strain(&self, p: &[Point], u: &[[f64; 2]]) -> SVector<f64, 3> {
        let (b, _) = strain(corners(p));
        b * SVector::<f64, 6>::from_iterator(u.iter().flatten().copied())
    }

    /// Barycentric coordinates, accepted down to −tol/|p₀p₁| (a point `tol` outside an edge).
    fn weights_at(&self, p: &[Point], point: Point, tol: f64) -> Option<Vec<f64>> {
        let [a, b, d] = corners(p);
        let area = geometry::orient(a, b, d);
        let w = [
            geometry::orient(point, b, d) / area,
            geometry::orient(a, point, d) / area,
            geometry::orient(a, b, point) / area,
        ];
        let eps = tol / geometry::distance(a, b).max(f64::MIN_POSITIVE);
        w.iter().all(|x| *x >= -eps).then(|| w.to_vec())
    }
}
