//! `signorini check`: everything `solve` verifies before it runs a backend, without the solve.
//!
//! `check` and `solve` share one path: the scene is parsed and validated, the element count of
//! every body is estimated and the total refused if it exceeds the limit, then the scene is meshed
//! and assembled exactly as `solve` would.  So a scene that `check` calls valid fails in `solve`
//! only by the solver's own verdict, never by a refusal `check` could have made.

use signorini_core::mesh::{estimate_elements, MeshLimits};
use signorini_core::scene::Scene;

use crate::run::{self, RunError};

/// What `check` found out about a valid scene.
#[derive(Debug, Clone)]
pub struct CheckReport {
    /// Per body: name, hmax and the estimated element count.
    pub bodies: Vec<(String, f64, usize)>,
    /// Estimated elements over all bodies.
    pub estimated_elements: usize,
    /// Elements actually meshed.
    pub elements: usize,
    /// Free DOFs of the assembled QP.
    pub dofs: usize,
    /// Contact rows.
    pub constraints: usize,
}

/// Validates `scene` the way `solve` does (up to and including assembly).
pub fn check(scene: &Scene, limits: &MeshLimits) -> Result<CheckReport, RunError> {
    let bodies: Vec<(String, f64, usize)> = scene
        .bodies
        .iter()
        .map(|b| {
            (
                b.name.clone(),
                b.hmax,
                estimate_elements(&b.polygon, b.hmax, b.element),
            )
        })
        .collect();
    let estimated_elements = bodies.iter().map(|b| b.2).fold(0usize, usize::saturating_add);
    let prepared = run::prepare(scene, limits)?;
    let model = &prepared.model;
    Ok(CheckReport {
        bodies,
        estimated_elements,
        elements: model.meshes.iter().map(|m| m.cells.len()).sum(),
        dofs: model.free.len(),
        constraints: model.rows(),
    })
}
