//! The body force (`[model] gravity` with each body's `density`): consistent nodal forces from
//! each element, and the resultant mass × g (for the force balance).

use super::{Contribution, Discretisation, Effect, EffectError, ModelParts};
use crate::fem::element;
use crate::fem::Dofs;
use crate::geometry::{self, Point};
use crate::mesh::Mesh;
use crate::scene::Scene;

/// Gravity on every body with a density.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyForce {
    /// Acceleration g.
    pub gravity: [f64; 2],
    /// Mass density per body (0 for a body without `density`).
    pub density: Vec<f64>,
    /// Out-of-plane thickness.
    pub thickness: f64,
}

impl BodyForce {
    /// The scene's gravity `g` with its bodies' densities.
    pub fn of(scene: &Scene, g: [f64; 2]) -> Self {
        Self {
            gravity: g,
            density: scene
                .bodies
                .iter()
                .map(|b| b.density.unwrap_or(0.0))
                .collect(),
            thickness: scene.thickness,
        }
    }

    /// Adds every element's consistent nodal forces of ρg to `f`.
    pub fn add_nodal(&self, meshes: &[Mesh], dofs: &Dofs, f: &mut [f64]) {
        let g = self.gravity;
        for (b, (mesh, rho)) in meshes.iter().zip(&self.density).enumerate() {
            let force = [rho * g[0], rho * g[1]];
            let element = element::of(mesh.cells.kind());
            let mut points = Vec::with_capacity(element.nodes());
            for c in 0..mesh.cells.len() {
                mesh.cell_points_into(c, &mut points);
                let fe = element.body_force(&points, force, self.thickness);
                for (a, &n) in mesh.cells.cell(c).iter().enumerate() {
                    f[dofs.dof(b, n, 0)] += fe[2 * a];
                    f[dofs.dof(b, n, 1)] += fe[2 * a + 1];
                }
            }
        }
    }

    /// Adds each body's weight ρ·|area of its outline|·t·g to its entry of `applied`
    /// (`outlines[b]`: body `b`'s outline, counter-clockwise).
    pub fn add_resultants(&self, outlines: &[&[Point]], applied: &mut [[f64; 2]]) {
        for ((outline, rho), applied) in outlines.iter().zip(&self.density).zip(applied) {
            let mass = rho * geometry::signed_area(outline).abs() * self.thickness;
            for (a, g) in applied.iter_mut().zip(self.gravity) {
                *a += mass * g;
            }
        }
    }
}

impl Contribution for BodyForce {
    fn effect(&self) -> Effect {
        Effect::Gravity
    }

    fn contribute(
        &self,
        on: Discretisation<'_>,
        parts: &mut ModelParts,
    ) -> Result<(), EffectError> {
        self.add_nodal(on.meshes, on.dofs, &mut parts.load);
        Ok(())
    }
}
