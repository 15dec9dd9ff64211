//! `signorini check`: everything `solve` verifies before it runs a backend, without the solve.
//!
//! `check` and `solve` share one path: the scene is parsed and validated, the element count of
//! every body is estimated and the total refused if it exceeds the limit, then the scene is meshed
//! and assembled exactly as `solve` would ([`run::prepare`], which repeats the estimate).  So a scene that `check` calls valid fails in `solve`
//! only by the solver's own verdict, never by a refusal `check` could have made.

use signorini_core::mesh::MeshLimits;
use signorini_core::preflight::{preflight, Preflight};
use signorini_core::scene::Scene;

use crate::run::{self, RunError};

/// What `check` found out about a valid scene.
#[derive(Debug, Clone)]
pub struct CheckReport {
    /// The estimates made before meshing (elements, nodes, DOFs, memory), per body and in total.
    pub estimate: Preflight,
    /// Elements actually meshed.
    pub elements: usize,
    /// Free DOFs of the assembled QP.
    pub dofs: usize,
    /// Contact rows.
    pub constraints: usize,
}

/// Validates `scene` the way `solve` does (up to and including assembly).
pub fn check(scene: &Scene, limits: &MeshLimits) -> Result<CheckReport, RunError> {
    let estimate = preflight(scene, limits)?;
    let prepared = run::prepare(scene, limits)?;
    let model = &prepared.model;
    Ok(CheckReport {
        estimate,
        elements: model.meshes.iter().map(|m| m.cells.len()).sum(),
        dofs: model.free.len(),
        constraints: model.rows(),
    })
}
