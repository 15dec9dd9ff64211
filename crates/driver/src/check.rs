//! `signorini check`: everything `solve` verifies before it runs a backend, without the solve.
//!
//! `check` and `solve` share one path: the scene is parsed and validated, the element count of
//! every body is estimated and the total refused if it exceeds the limit, then the scene is meshed
//! and assembled exactly as `solve` would ([`run::prepare`], which repeats the estimate).  So a scene that `check` calls valid fails in `solve`
//! only by the solver's own verdict, never by a refusal `check` could have made.
//!
//! It also prices every backend's run — the peak `solve` checks before the backend runs, the
//! solve path's copies and the backend's own part ([`crate::guard`]) — so that a user sees which
//! backend will not fit, and `solve` refuses exactly those (exit 3, the same figure).

use signorini_core::memory;
use signorini_core::mesh::MeshLimits;
use signorini_core::model::Model;
use signorini_core::preflight::{check_factor_memory, preflight, Preflight, PreflightError};
use signorini_core::qp::{QpError, QpProblem};
use signorini_core::scene::Scene;

use crate::backends::BackendKind;
use crate::guard::RunShape;
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
    /// Every backend's memory need, from the symbolic analyses.
    pub memory: MemoryNeeds,
}

pub use crate::guard::BackendNeed;

/// The memory of a run, per backend, estimated after assembly and before any factorisation.
#[derive(Debug, Clone, PartialEq)]
pub struct MemoryNeeds {
    /// The sparse factor of A, its scratch, A, B and the vectors
    /// ([`signorini_core::memory::FactorEstimate`]); every command refuses a scene where this
    /// alone does not fit.
    pub base: f64,
    /// Each backend of this build ([`BackendKind::ALL`], auto and the condensed-dual forms):
    /// the run's peak with it (none without contact rows: no backend runs).
    pub backends: Vec<BackendNeed>,
    /// Memory available ([`memory::available_bytes`]), bytes.
    pub available: Option<u64>,
}

impl MemoryNeeds {
    /// The backend that needs the most.
    pub fn largest(&self) -> Option<&BackendNeed> {
        self.backends
            .iter()
            .max_by(|a, b| a.bytes.total_cmp(&b.bytes))
    }
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
        memory: memory_needs(&prepared.model, &prepared.qp)?,
    })
}

/// Every backend's memory need for a run of `model`'s QP `qp` (see [`MemoryNeeds`]): the
/// run's peak as `solve` prices it before the backend runs ([`crate::guard`]), so that `check`
/// and `solve` agree.
pub fn memory_needs(model: &Model, qp: &QpProblem) -> Result<MemoryNeeds, RunError> {
    let (base, _) = check_factor_memory(qp, u64::MAX)?;
    let failed = |kind: BackendKind, e: QpError| {
        RunError::Preflight(PreflightError::Analysis(format!("{}: {e}", kind.name())))
    };
    let mut backends = Vec::new();
    if qp.rows() > 0 {
        let shape = RunShape::of(model, qp).map_err(|e| failed(BackendKind::Auto, e))?;
        let kinds = BackendKind::ALL
            .into_iter()
            .chain(BackendKind::EXTRA)
            .filter(|k| k.available());
        for kind in kinds {
            backends.push(shape.need(kind).map_err(|e| failed(kind, e))?);
        }
    }
    Ok(MemoryNeeds {
        base: base.total(),
        backends,
        available: memory::available_bytes(),
    })
}
