//! The fields of each body after a solve — displacements, stresses, von Mises, contact
//! pressures — their interpolation at a point (probes), and the threshold of active contact.

use crate::fem::{self, element};
use crate::geometry::Point;
use crate::mesh::{Cells, Mesh};
use crate::model::Model;
use crate::solve::Solution;

/// Per-body fields for output files.
#[derive(Debug, Clone)]
pub struct BodyFields {
    /// Nodal displacements.
    pub displacement: Vec<[f64; 2]>,
    /// Stresses (σₓₓ, σᵧᵧ, σₓᵧ, σ_zz) per cell.
    pub stress: Vec<[f64; 4]>,
    /// Von Mises stress per cell.
    pub von_mises: Vec<f64>,
    /// Contact pressure per node (0 away from contact).
    pub contact_pressure: Vec<f64>,
}

/// A row counts as active when its multiplier exceeds 10⁻⁶ of the force scale (the larger of the
/// largest multiplier and the total applied load), so round-off multipliers never count.
pub fn is_active(multiplier: f64, force_scale: f64) -> bool {
    multiplier > 1e-6 * force_scale && multiplier > 0.0
}

/// Displacement at `point` of a mesh by interpolation (`None` if the point is in no cell).
pub fn interpolate(mesh: &Mesh, u: &[[f64; 2]], point: Point, tol: f64) -> Option<[f64; 2]> {
    let combine = |nodes: &[usize], w: &[f64]| {
        let mut r = [0.0, 0.0];
        for (n, wi) in nodes.iter().zip(w) {
            r[0] += wi * u[*n][0];
            r[1] += wi * u[*n][1];
        }
        r
    };
    match &mesh.cells {
        Cells::Triangles(t) => t.iter().find_map(|c| {
            let [a, b, d] = c.map(|n| mesh.nodes[n]);
            let area = crate::geometry::orient(a, b, d);
            let w = [
                crate::geometry::orient(point, b, d) / area,
                crate::geometry::orient(a, point, d) / area,
                crate::geometry::orient(a, b, point) / area,
            ];
            let eps = tol / crate::geometry::distance(a, b).max(f64::MIN_POSITIVE);
            w.iter().all(|x| *x >= -eps).then(|| combine(c, &w))
        }),
        Cells::Quads(q) => q.iter().find_map(|c| {
            let p = c.map(|n| mesh.nodes[n]);
            let (xi, eta) = quad_local(p, point)?;
            let eps = 1e-9;
            if xi.abs() > 1.0 + eps || eta.abs() > 1.0 + eps {
                return None;
            }
            let w = [
                0.25 * (1.0 - xi) * (1.0 - eta),
                0.25 * (1.0 + xi) * (1.0 - eta),
                0.25 * (1.0 + xi) * (1.0 + eta),
                0.25 * (1.0 - xi) * (1.0 + eta),
            ];
            Some(combine(c, &w))
        }),
    }
}

/// Local coordinates (ξ, η) of a point in a bilinear quad, by Newton's method.
fn quad_local(p: [Point; 4], x: Point) -> Option<(f64, f64)> {
    let (mut xi, mut eta) = (0.0_f64, 0.0_f64);
    for _ in 0..30 {
        let n = [
            0.25 * (1.0 - xi) * (1.0 - eta),
            0.25 * (1.0 + xi) * (1.0 - eta),
            0.25 * (1.0 + xi) * (1.0 + eta),
            0.25 * (1.0 - xi) * (1.0 + eta),
        ];
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

/// Fields per body (displacement, stresses, contact pressure) for the output files.
pub fn body_fields(model: &Model, solution: &Solution) -> Vec<BodyFields> {
    let mut fields: Vec<BodyFields> = model
        .meshes
        .iter()
        .enumerate()
        .map(|(b, mesh)| {
            let displacement = model.body_displacements(b, &solution.displacement);
            let stress = fem::cell_stresses(mesh, &model.materials[b], &displacement);
            let von_mises = stress.iter().map(|s| element::von_mises(*s)).collect();
            BodyFields {
                displacement,
                stress,
                von_mises,
                contact_pressure: vec![0.0; mesh.nodes.len()],
            }
        })
        .collect();
    // Only active rows carry pressure into the fields: round-off multipliers (1e-17 from an
    // interior-point method) must not mark a node as in contact in the VTU or the SVG.
    let scale = active_scale(model, solution);
    let mut row = 0;
    for pair in &model.contacts {
        for r in &pair.rows {
            if let Some(&l) = solution.multipliers.get(row) {
                if is_active(l, scale) {
                    fields[pair.slave].contact_pressure[r.slave_node] += l / r.tributary;
                }
            }
            row += 1;
        }
    }
    fields
}

/// The force scale of [`is_active`] for a solution: the larger of the largest multiplier and the
/// total applied load Σ|fᵢ|.
pub fn active_scale(model: &Model, solution: &Solution) -> f64 {
    solution
        .multipliers
        .iter()
        .copied()
        .fold(0.0, f64::max)
        .max(model.load.iter().map(|f| f.abs()).sum())
}
