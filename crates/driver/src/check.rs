//! `signorini check`: everything `solve` verifies before it runs a backend, without the solve.
//!
//! `check` and `solve` share one path: the scene is parsed and validated, the element count of
//! every body is estimated and the total refused if it exceeds the limit, then the scene is meshed
//! and assembled exactly as `solve` would ([`run::prepare`], which repeats the estimate).  So a scene that `check` calls valid fails in `solve`
//! only by the solver's own verdict, never by a refusal `check` could have made.
//!
//! It also prices every backend's memory from the symbolic analyses the backends themselves
//! run before allocating ([`MemoryNeeds`]), so that a user sees which backend will not fit.

use signorini_core::memory::{self, FactorEstimate, KktEstimate};
use signorini_core::mesh::MeshLimits;
use signorini_core::preflight::{check_factor_memory, preflight, Preflight, PreflightError};
use signorini_core::qp::{QpError, QpProblem, BYTES_PER_DUAL_ENTRY};
use signorini_core::scene::Scene;

use crate::backends::BackendKind;
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

/// One backend's estimated peak memory.
#[derive(Debug, Clone, PartialEq)]
pub struct BackendNeed {
    /// The backend's command-line name.
    pub backend: &'static str,
    /// Bytes.
    pub bytes: f64,
    /// What the bytes are for.
    pub what: String,
}

/// The memory of a run, per backend, estimated after assembly and before any factorisation.
#[derive(Debug, Clone, PartialEq)]
pub struct MemoryNeeds {
    /// What every run holds: the sparse factor of A (the timing floor and the dual backends
    /// factor it), its scratch, A, B and the vectors ([`FactorEstimate`]); `solve` refuses a
    /// scene where this alone does not fit.
    pub base: f64,
    /// Each backend of this build ([`BackendKind::ALL`] and the condensed-dual forms).
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
        memory: memory_needs(&prepared.qp)?,
    })
}

/// Every backend's memory need for `qp` (see [`MemoryNeeds`]).
pub fn memory_needs(qp: &QpProblem) -> Result<MemoryNeeds, RunError> {
    let (base, _) = check_factor_memory(qp, u64::MAX)?;
    let kinds = BackendKind::ALL
        .into_iter()
        .chain(BackendKind::EXTRA)
        .filter(|k| k.available() && *k != BackendKind::Auto);
    let mut backends = Vec::new();
    for kind in kinds {
        backends.push(need_of(kind, qp, &base).map_err(|e| {
            RunError::Preflight(PreflightError::Analysis(format!("{}: {e}", kind.name())))
        })?);
    }
    Ok(MemoryNeeds {
        base: base.total(),
        backends,
        available: memory::available_bytes(),
    })
}

/// One backend's need: its KKT factor (clarabel, osqp, pdas) or the factor of A plus its dense
/// m × m arrays (the dual backends, the condensed-dual forms).
fn need_of(
    kind: BackendKind,
    qp: &QpProblem,
    base: &FactorEstimate,
) -> Result<BackendNeed, QpError> {
    let m = qp.rows() as f64;
    let kkt = |estimate: KktEstimate, factors: &str| BackendNeed {
        backend: kind.name(),
        bytes: estimate.total(),
        what: format!(
            "{factors} of the {d}×{d} KKT matrix (nnz(L) = {v:.3e}), copies and vectors",
            d = estimate.dim,
            v = estimate.nnz_l as f64
        ),
    };
    let dense = |squares: f64, what: &str| BackendNeed {
        backend: kind.name(),
        bytes: base.total() + 8.0 * squares * m * m,
        what: format!("the factor of A and {what}"),
    };
    Ok(match kind {
        BackendKind::Clarabel => kkt(signorini_clarabel::memory_need(qp)?, "the LDLᵀ factor"),
        #[cfg(feature = "osqp")]
        BackendKind::Osqp => kkt(
            signorini_osqp::memory_need(qp)?,
            "two LDLᵀ factors (ADMM's, the polish's)",
        ),
        BackendKind::Pdas => kkt(
            signorini_pdas::memory_need(qp)?,
            "the LDLᵀ factor",
        ),
        BackendKind::DualPgs => dense(1.0, "the dense dual Hessian H (m × m)"),
        BackendKind::DualSsn => dense(
            4.0,
            "H, its Newton matrix, a shifted copy and their factor (matrix-free below that: the factor of A alone)",
        ),
        BackendKind::DualUzawa => dense(0.0, "no dense matrix"),
        _ => dense(
            BYTES_PER_DUAL_ENTRY / 8.0,
            "the condensed dual H with the inner solver's copy",
        ),
    })
}
