//! The fields of each body after a solve — displacements, stresses, von Mises, contact
//! pressures, friction fields — and their interpolation at a point (probes).

use super::active::{active_scale, is_active};
use crate::fem::{self, element};
use crate::geometry::Point;
use crate::mesh::Mesh;
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
    /// Tangential traction, slip and state per node, when the model has friction.
    pub friction: Option<super::friction::FrictionField>,
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
    let element = element::of(mesh.cells.kind());
    let mut points = Vec::with_capacity(element.nodes());
    (0..mesh.cells.len()).find_map(|c| {
        mesh.cell_points_into(c, &mut points);
        let w = element.weights_at(&points, point, tol)?;
        Some(combine(mesh.cells.cell(c), &w))
    })
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
                friction: None,
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
    if let Some(friction) = super::friction::friction_fields(model, solution, scale) {
        for (f, t) in fields.iter_mut().zip(friction) {
            f.friction = Some(t);
        }
    }
    fields
}
