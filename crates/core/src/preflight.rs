//! Preflight: what a scene will cost, estimated from the scene alone before anything is meshed,
//! and refused when the whole scene (all bodies together) exceeds the element limit.
//!
//! The per-body guard of [`crate::mesh::mesh_body`] cannot see that three bodies just under the limit
//! each add up to three times it (such a scene used to abort with an out-of-memory SIGABRT after
//! 55 s); [`preflight`] refuses the total, and says how much memory the solve would take.
//! `signorini check` and `signorini solve` are both meant to call it, so that they agree.
//!
//! ```
//! use signorini_core::mesh::MeshLimits;
//! use signorini_core::preflight::{preflight, PreflightError};
//! use signorini_core::scene::Scene;
//! let scene = Scene::from_toml(r#"
//!     [[body]]
//!     name = "block"
//!     polygon = [[0, 0], [1, 0], [1, 1], [0, 1]]
//!     hmax = 0.1
//!     young = 1.0
//!     poisson = 0.3
//!     [[dirichlet]]
//!     body = "block"
//!     region = [0, 1, 0, 0]
//! "#).unwrap();
//! let p = preflight(&scene, &MeshLimits::default()).unwrap();
//! assert_eq!(p.bodies[0].name, "block");
//! assert_eq!(p.elements, p.bodies[0].elements);
//! let small = MeshLimits { max_elements: 10, ..MeshLimits::default() };
//! let err = preflight(&scene, &small).unwrap_err();
//! assert!(err.to_string().contains("GiB"));
//! ```

use crate::linalg::{CholeskyPattern, FactorInfo};
use crate::memory::FactorEstimate;
use crate::mesh::{estimate_elements_refined, estimate_nodes_refined, MeshLimits};
use crate::qp::QpProblem;
use crate::scene::Scene;

/// Resident memory of the process before any scene-sized allocation, in bytes (measured: 9 MiB
/// peak for a whole solve at 2 124 DOFs; rounded up).
const BASE_BYTES: f64 = 16.0 * 1024.0 * 1024.0;

/// Peak bytes per DOF·log₂(DOF) of a solve with a backend that factorises the KKT system
/// (clarabel, the default, and osqp).  Measured with `/usr/bin/time -v signorini solve` on
/// Experiment 3 (two bodies, both refined) on the development machine:
///
/// | DOFs | clarabel | osqp | dual-ssn | dual-pgs |
/// |---:|---:|---:|---:|---:|
/// | 30 002 | 75 MiB (158) | 103 MiB (223) | 48 MiB (110) | |
/// | 117 572 | 312 MiB (161) | 468 MiB (244) | 176 MiB (89) | |
/// | 237 478 | 669 MiB (163) | 983 MiB (241) | | |
/// | 461 680 | 1 413 MiB (170) | 2 062 MiB (248) | 809 MiB (97) | 809 MiB (97) |
/// | 938 496 | | | 1 683 MiB (94) | |
///
/// (in brackets: (peak − 8 MiB) / (DOF·log₂ DOF)).  The coefficient grows slowly with the size
/// (fill-in of the factorisation); 280 covers osqp, the largest, with a margin.
const FACTORISING_BYTES_PER_DOF_LOG: f64 = 280.0;

/// Peak bytes per DOF·log₂(DOF) of a solve with a dual backend (dual-pgs, dual-uzawa, dual-ssn:
/// one Cholesky factor of A plus vectors), from the same measurements; 110 covers them.
const DUAL_BYTES_PER_DOF_LOG: f64 = 110.0;

/// The estimate for one body.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyEstimate {
    /// The body's name.
    pub name: String,
    /// Estimated elements ([`crate::mesh::estimate_elements_refined`]: fine uniform P1 meshes
    /// over-estimated by 8–15 %, graded ones within ±30 %, Q1 exact up to break points).
    pub elements: usize,
    /// Estimated nodes ([`crate::mesh::estimate_nodes_refined`]).
    pub nodes: usize,
    /// Estimated degrees of freedom: two per node, before the Dirichlet DOFs are removed.
    pub dofs: usize,
}

/// What a scene will cost, estimated before meshing.  Every count saturates at `usize::MAX`
/// and every byte figure at `u64::MAX`: nothing here wraps.
#[derive(Debug, Clone, PartialEq)]
pub struct Preflight {
    /// One estimate per body, in the scene's order.
    pub bodies: Vec<BodyEstimate>,
    /// Estimated elements of all bodies together.
    pub elements: usize,
    /// Estimated nodes of all bodies together.
    pub nodes: usize,
    /// Estimated degrees of freedom of all bodies together (Dirichlet DOFs included).
    pub dofs: usize,
    /// Estimated peak resident memory, in bytes, of a whole `solve` (mesh, assembly, the
    /// backend, the report) with a backend that factorises the KKT system: clarabel (the
    /// default) or osqp, the hungriest.  An upper estimate: the fit covers the measured peaks
    /// with a margin, and the DOFs are over-estimated.  Does not cover `compare` or `sweep`,
    /// which hold several backends' results.
    pub bytes: u64,
    /// The same for the dual backends (dual-pgs, dual-uzawa, dual-ssn), which need about 40 %
    /// of [`Preflight::bytes`].
    pub bytes_dual: u64,
}

/// Why [`preflight`] refused a scene.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PreflightError {
    /// The estimated total of elements over all bodies exceeds [`MeshLimits::max_elements`].
    #[error(
        "the scene would mesh into {} elements over all {} bodies ({}), more than the \
         limit of {limit}; solving it would take about {} of memory ({} with a dual backend); \
         increase hmax or raise the element limit (--max-elements)",
        count(.preflight.elements),
        .preflight.bodies.len(),
        body_list(&.preflight.bodies),
        gib(.preflight.bytes),
        gib(.preflight.bytes_dual)
    )]
    TooManyElements {
        /// The limit.
        limit: usize,
        /// The estimates that exceed it.
        preflight: Box<Preflight>,
    },
    /// After assembly, the symbolic analysis of A shows that its sparse factor and the run's
    /// matrices would not fit in the memory available.
    #[error(
        "the run would need about {} of memory but {} is available: the sparse Cholesky factor \
         of the stiffness ({dofs} DOFs, {ordering} ordering, nnz(L) = {nnz_l}) takes {} and its \
         scratch space {}, the matrices and vectors {}; increase hmax",
        gib(*.needed),
        gib(*.available),
        gib(*.factor),
        gib(*.scratch),
        gib(*.rest)
    )]
    FactorTooLarge {
        /// Free DOFs.
        dofs: usize,
        /// The ordering the factor would use.
        ordering: String,
        /// Nonzeros of L.
        nnz_l: usize,
        /// Bytes of the factor's values.
        factor: u64,
        /// Bytes of the numeric factorisation's scratch.
        scratch: u64,
        /// Bytes of the matrices and vectors.
        rest: u64,
        /// Total bytes needed.
        needed: u64,
        /// Bytes available.
        available: u64,
    },
    /// The symbolic analysis itself failed (the ordering could not be allocated, say).
    #[error("the symbolic analysis of the stiffness failed: {0}")]
    Analysis(String),
}

/// After assembly, before any numeric factorisation: orders and analyses A the way every factor
/// of it is built ([`CholeskyPattern::analyse`]), estimates the run's peak
/// ([`FactorEstimate`]) and refuses it when that exceeds `available` bytes.  Returns the
/// estimate and the factor's description.
///
/// # Errors
/// [`PreflightError::FactorTooLarge`] when the estimate exceeds `available`;
/// [`PreflightError::Analysis`] when the analysis fails.
pub fn check_factor_memory(
    qp: &QpProblem,
    available: u64,
) -> Result<(FactorEstimate, FactorInfo), PreflightError> {
    // A stiffness stores its whole diagonal, so the floor's shifted A + εI has A's pattern.
    let pattern = CholeskyPattern::analyse(&qp.stiffness)
        .map_err(|e| PreflightError::Analysis(e.to_string()))?;
    let estimate = FactorEstimate::of(qp, &pattern);
    let info = pattern
        .info(&qp.stiffness)
        .map_err(|e| PreflightError::Analysis(e.to_string()))?;
    // `as` saturates: the byte figures are finite and nonnegative.
    if estimate.total() > available as f64 {
        return Err(PreflightError::FactorTooLarge {
            dofs: qp.dofs(),
            ordering: info.ordering.as_str().to_string(),
            nnz_l: info.nnz_l,
            factor: estimate.factor as u64,
            scratch: estimate.scratch as u64,
            rest: (estimate.matrices + estimate.vectors) as u64,
            needed: estimate.total() as u64,
            available,
        });
    }
    Ok((estimate, info))
}

fn body_list(bodies: &[BodyEstimate]) -> String {
    let parts: Vec<String> = bodies
        .iter()
        .map(|b| format!("{:?} {}", b.name, count(b.elements)))
        .collect();
    parts.join(", ")
}

/// An estimated count for a message: `~N`, or "over 1.8e19" when it saturated at `usize::MAX`.
pub fn count(n: usize) -> String {
    if n == usize::MAX {
        format!("over {:.1e}", usize::MAX as f64)
    } else {
        format!("~{n}")
    }
}

/// Bytes as GiB for a message: one decimal, or scientific notation when huge, and the MiB
/// besides below 1 GiB (where "0.0 GiB" would say nothing).
pub fn gib(bytes: u64) -> String {
    gib_f64(bytes as f64 / (1024.0 * 1024.0 * 1024.0))
}

pub use signorini_qp::memory::gib_f64;

/// Estimated peak bytes of a solve with `dofs` unknowns: base + coefficient · n log₂ n,
/// saturating at `u64::MAX`.
fn peak_bytes(dofs: usize, per_dof_log: f64) -> u64 {
    let n = dofs as f64;
    let bytes = BASE_BYTES + per_dof_log * n * n.max(2.0).log2();
    // `as` saturates at u64::MAX (and the value is never NaN: n ≥ 0).
    bytes as u64
}

/// Estimates, per body and in total, the elements, nodes, DOFs and peak memory of solving
/// `scene`, from its polygons, `hmax` and refine regions alone (nothing is meshed or allocated beyond the
/// result).
///
/// The memory model ([`Preflight::bytes`]) is base + c · DOF · log₂ DOF with c fitted to whole
/// `signorini solve` runs on this project's development machine (see the constants in the
/// source); it covers meshing, assembly, one backend's solve and the report, not `compare` or
/// `sweep`.
///
/// # Errors
/// [`PreflightError::TooManyElements`] when the total over all bodies exceeds
/// `limits.max_elements`; the message gives the total, the limit and the memory it would take.
pub fn preflight(scene: &Scene, limits: &MeshLimits) -> Result<Preflight, PreflightError> {
    let bodies: Vec<BodyEstimate> = scene
        .bodies
        .iter()
        .map(|b| {
            if let Some(m) = &b.imported {
                // A Gmsh body's counts are exact.
                let nodes = m.mesh.nodes.len();
                return BodyEstimate {
                    name: b.name.clone(),
                    elements: m.mesh.cells.len(),
                    nodes,
                    dofs: nodes.saturating_mul(2),
                };
            }
            let nodes = estimate_nodes_refined(&b.polygon, b.hmax, &b.refine, b.element);
            BodyEstimate {
                name: b.name.clone(),
                elements: estimate_elements_refined(&b.polygon, b.hmax, &b.refine, b.element),
                nodes,
                dofs: nodes.saturating_mul(2),
            }
        })
        .collect();
    let sum = |f: fn(&BodyEstimate) -> usize| bodies.iter().map(f).fold(0, usize::saturating_add);
    let elements = sum(|b| b.elements);
    let nodes = sum(|b| b.nodes);
    let dofs = sum(|b| b.dofs);
    let preflight = Preflight {
        elements,
        nodes,
        dofs,
        bytes: peak_bytes(dofs, FACTORISING_BYTES_PER_DOF_LOG),
        bytes_dual: peak_bytes(dofs, DUAL_BYTES_PER_DOF_LOG),
        bodies,
    };
    if preflight.elements > limits.max_elements {
        return Err(PreflightError::TooManyElements {
            limit: limits.max_elements,
            preflight: Box::new(preflight),
        });
    }
    Ok(preflight)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model;
    use crate::scene::Scene;

    fn block_qp() -> QpProblem {
        let scene = Scene::from_toml(
            r#"
            [[body]]
            name = "block"
            polygon = [[0, 0], [1, 0], [1, 1], [0, 1]]
            hmax = 0.05
            young = 1.0
            poisson = 0.3
            [[dirichlet]]
            body = "block"
            region = [0, 1, 0, 0]
            "#,
        )
        .unwrap();
        let meshes = model::mesh_scene(&scene, &MeshLimits::default()).unwrap();
        model::assemble(&scene, meshes).unwrap().qp
    }

    #[test]
    fn the_factor_check_refuses_exactly_above_its_estimate() {
        let qp = block_qp();
        let (estimate, info) = check_factor_memory(&qp, u64::MAX).unwrap();
        // Independent lower bounds: 8 B per nonzero of L, 12 B per nonzero of A.
        assert!(estimate.factor >= 8.0 * info.nnz_l as f64);
        assert!(estimate.matrices >= 12.0 * qp.stiffness.nnz() as f64);
        let needed = estimate.total().ceil() as u64;
        assert!(check_factor_memory(&qp, needed).is_ok());
        let err = check_factor_memory(&qp, needed / 2).unwrap_err();
        let PreflightError::FactorTooLarge {
            needed: n, nnz_l, ..
        } = &err
        else {
            panic!("{err}");
        };
        assert_eq!(*nnz_l, info.nnz_l);
        assert!(*n <= needed && *n > needed / 2);
        assert!(err.to_string().contains("GiB"), "{err}");
    }
}
