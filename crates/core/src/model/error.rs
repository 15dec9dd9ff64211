//! Why a scene could not be turned into a model.

use crate::contact::ContactError;
use crate::effects::EffectError;
use crate::fem::FemError;
use crate::geometry::Point;
use crate::mesh::MeshError;
use crate::qp::QpError;

/// Why a scene could not be turned into a model.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// Meshing failed or was refused.
    #[error("body \"{body}\" cannot be meshed")]
    Mesh {
        /// Body name.
        body: String,
        /// Cause.
        source: MeshError,
    },
    /// Supports or loads are inconsistent with the mesh.
    #[error(transparent)]
    Fem(#[from] FemError),
    /// Contact rows could not be built.
    #[error(transparent)]
    Contact(#[from] ContactError),
    /// The reduced load or gaps overflow the floating-point range (checked before the QP is
    /// built, so that the refusal names the scene keys rather than the QP's vectors).
    #[error("{what} overflows the floating-point range (beyond ±1.8e308): {cause}; rescale the scene's units")]
    Overflow {
        /// Which vector ("the load after lifting the prescribed displacements", ...).
        what: &'static str,
        /// The scene keys whose product overflowed.
        cause: &'static str,
    },
    /// A body can move rigidly and nothing (no support, no contact) holds it.
    #[error("body \"{body}\" is not held: {modes} rigid-body mode(s) are free and it is in no contact pair; add a [[dirichlet]] support")]
    Unsupported {
        /// Body name.
        body: String,
        /// Number of free rigid-body modes.
        modes: usize,
    },
    /// A body with free rigid-body modes is in contact pairs, but no contact row acts on it, so
    /// nothing holds it (found at assembly, before any backend runs).
    #[error("body \"{body}\" is held only by contact ({modes} rigid-body mode(s) free), but its contact pair(s) {pairs} gave no constraint row acting on it; check the pair's region box and the bodies' positions, or add a [[dirichlet]] support")]
    NotHeld {
        /// Body name.
        body: String,
        /// Number of free rigid-body modes.
        modes: usize,
        /// The body's pairs, e.g. `#1 ("block" – "base")`, comma-separated.
        pairs: String,
    },
    /// A contact row whose every DOF is prescribed has a negative reduced gap g − B_D u_D: the
    /// prescribed displacements alone push the slave node into the master.
    #[error("contact #{pair} (slave \"{slave}\", master \"{master}\"): at ({x}, {y}) both sides are fixed by [[dirichlet]] conditions whose prescribed displacements make the bodies interpenetrate by {depth:e}; the supports contradict the contact", x = point[0], y = point[1], depth = -gap)]
    PrescribedPenetration {
        /// 1-based pair index.
        pair: usize,
        /// Slave body name.
        slave: String,
        /// Master body name.
        master: String,
        /// Slave node position (undeformed).
        point: Point,
        /// The reduced gap g − B_D u_D (< 0).
        gap: f64,
    },
    /// The reduced QP failed its checks.
    #[error(transparent)]
    Qp(#[from] QpError),
}

impl From<EffectError> for ModelError {
    /// An effect's refusal, as the model's error of the same kind (the chain stays one level).
    fn from(e: EffectError) -> Self {
        match e {
            EffectError::Fem(e) => ModelError::Fem(e),
            EffectError::Contact(e) => ModelError::Contact(e),
        }
    }
}
