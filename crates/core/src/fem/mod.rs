//! Finite elements: element matrices, sparse assembly, loads, supports and stress recovery.
//!
//! Unknowns are numbered node by node across bodies: node `i` of body `b` has the global node
//! number `offset(b) + i` and the DOFs `2·(offset(b) + i)` (x) and `2·(offset(b) + i) + 1` (y).

pub mod assembly;
pub mod element;

use crate::geometry;
use crate::mesh::Mesh;

pub use assembly::assemble_stiffness;
pub use element::{von_mises, Material};

/// Global numbering of the nodes and DOFs of all bodies.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Dofs {
    offsets: Vec<usize>,
}

impl Dofs {
    /// Numbering for bodies with the given node counts.
    pub fn new(nodes_per_body: &[usize]) -> Self {
        let mut offsets = Vec::with_capacity(nodes_per_body.len() + 1);
        offsets.push(0);
        for n in nodes_per_body {
            offsets.push(offsets[offsets.len() - 1] + n);
        }
        Self { offsets }
    }

    /// First global node number of body `b`.
    pub fn node_offset(&self, b: usize) -> usize {
        self.offsets[b]
    }

    /// Total number of nodes.
    pub fn nodes(&self) -> usize {
        self.offsets[self.offsets.len() - 1]
    }

    /// Total number of DOFs (2 per node).
    pub fn len(&self) -> usize {
        2 * self.nodes()
    }

    /// True when there are no nodes.
    pub fn is_empty(&self) -> bool {
        self.nodes() == 0
    }

    /// Global DOF of component `c` (0 = x, 1 = y) of node `node` of body `b`.
    pub fn dof(&self, b: usize, node: usize, c: usize) -> usize {
        2 * (self.offsets[b] + node) + c
    }

    /// Global DOF range of body `b`.
    pub fn body_range(&self, b: usize) -> std::ops::Range<usize> {
        2 * self.offsets[b]..2 * self.offsets[b + 1]
    }
}

/// Why the FEM stage refused a scene.
#[derive(Debug, thiserror::Error)]
pub enum FemError {
    /// Two Dirichlet conditions prescribe different values to the same DOF.
    #[error("dirichlet #{first} and dirichlet #{second} prescribe different {component} displacements ({a} vs {b}) at node ({x}, {y}) of body \"{body}\"")]
    ConflictingDirichlet {
        /// 1-based index of the first condition.
        first: usize,
        /// 1-based index of the second condition.
        second: usize,
        /// Body name.
        body: String,
        /// "x" or "y".
        component: &'static str,
        /// Node x.
        x: f64,
        /// Node y.
        y: f64,
        /// First value.
        a: f64,
        /// Second value.
        b: f64,
    },
    /// A Dirichlet or Neumann region holds no node or edge of the mesh.
    #[error("{section}: region {region:?} holds no boundary {what} of body \"{body}\"'s mesh")]
    EmptyRegion {
        /// e.g. `dirichlet #1`.
        section: String,
        /// The region.
        region: [f64; 4],
        /// Body name.
        body: String,
        /// "node" or "edge".
        what: &'static str,
    },
}

pub use crate::mesh::boundary_nodes;

/// Stresses (σₓₓ, σᵧᵧ, σₓᵧ, σ_zz) per cell (P1: exact constant; Q1: at the centroid).
pub fn cell_stresses(mesh: &Mesh, material: &Material, displacement: &[[f64; 2]]) -> Vec<[f64; 4]> {
    let d = material.elasticity();
    let element = element::of(mesh.cells.kind());
    let (mut points, mut u) = (Vec::new(), Vec::new());
    (0..mesh.cells.len())
        .map(|c| {
            mesh.cell_points_into(c, &mut points);
            u.clear();
            u.extend(mesh.cells.cell(c).iter().map(|&n| displacement[n]));
            let s = d * element.centre_strain(&points, &u);
            [s[0], s[1], s[2], material.sigma_zz(s[0], s[1])]
        })
        .collect()
}

/// Rigid-body modes of body `b` that its fixed DOFs do not remove, as full-length DOF vectors
/// (zero outside the body).  Empty when the supports hold the body.
///
/// A mode u = (a − θ(y − ȳ), b + θ(x − x̄)) survives when every fixed DOF vanishes on it; the
/// surviving (a, b, θ) form the null space of a 3-column matrix, found from its Gram matrix.
pub fn free_rigid_modes(
    mesh: &Mesh,
    b: usize,
    dofs: &Dofs,
    fixed: &[Option<f64>],
) -> Vec<Vec<f64>> {
    let n = mesh.nodes.len();
    if n == 0 {
        return Vec::new();
    }
    let centre = mesh.nodes.iter().fold([0.0, 0.0], |c, p| {
        [c[0] + p[0] / n as f64, c[1] + p[1] / n as f64]
    });
    let bbox = geometry::bounding_box(mesh.nodes.iter());
    let size = (bbox[1] - bbox[0])
        .hypot(bbox[3] - bbox[2])
        .max(f64::MIN_POSITIVE);
    let mut gram = nalgebra::Matrix3::<f64>::zeros();
    for (i, p) in mesh.nodes.iter().enumerate() {
        let (x, y) = ((p[0] - centre[0]) / size, (p[1] - centre[1]) / size);
        if fixed[dofs.dof(b, i, 0)].is_some() {
            let r = nalgebra::Vector3::new(1.0, 0.0, -y);
            gram += r * r.transpose();
        }
        if fixed[dofs.dof(b, i, 1)].is_some() {
            let r = nalgebra::Vector3::new(0.0, 1.0, x);
            gram += r * r.transpose();
        }
    }
    let eig = gram.symmetric_eigen();
    let largest = eig.eigenvalues.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut modes = Vec::new();
    for k in 0..3 {
        if eig.eigenvalues[k].abs() > 1e-10 * largest.max(1.0) {
            continue;
        }
        let v = eig.eigenvectors.column(k);
        let mut mode = vec![0.0; dofs.len()];
        for (i, p) in mesh.nodes.iter().enumerate() {
            let (x, y) = ((p[0] - centre[0]) / size, (p[1] - centre[1]) / size);
            mode[dofs.dof(b, i, 0)] = v[0] - v[2] * y;
            mode[dofs.dof(b, i, 1)] = v[1] + v[2] * x;
        }
        modes.push(mode);
    }
    modes
}
