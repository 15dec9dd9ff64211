//! Finite elements: element matrices, sparse assembly, loads, supports and stress recovery.
//!
//! Unknowns are numbered node by node across bodies: node `i` of body `b` has the global node
//! number `offset(b) + i` and the DOFs `2·(offset(b) + i)` (x) and `2·(offset(b) + i) + 1` (y).

pub mod assembly;
pub mod element;

use crate::geometry::{self, Point};
use crate::mesh::{Cells, Mesh};
use crate::scene::Scene;

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

/// Prescribed DOF values from the scene's Dirichlet conditions: `Some(value)` for a fixed DOF.
pub fn prescribed(
    scene: &Scene,
    meshes: &[Mesh],
    dofs: &Dofs,
) -> Result<Vec<Option<f64>>, FemError> {
    let tol = scene.tolerance();
    let mut fixed: Vec<Option<(f64, usize)>> = vec![None; dofs.len()];
    for (k, d) in scene.dirichlet.iter().enumerate() {
        let mesh = &meshes[d.body];
        let mut matched = false;
        for n in boundary_nodes(mesh) {
            let p = mesh.nodes[n];
            if !d.selects_node(&scene.bodies[d.body], n, p, tol) {
                continue;
            }
            matched = true;
            for c in 0..2 {
                if !d.components[c] {
                    continue;
                }
                let dof = dofs.dof(d.body, n, c);
                let value = d.value[c];
                match fixed[dof] {
                    Some((old, first))
                        if (old - value).abs() > 1e-12 * old.abs().max(value.abs()) =>
                    {
                        return Err(FemError::ConflictingDirichlet {
                            first: first + 1,
                            second: k + 1,
                            body: scene.bodies[d.body].name.clone(),
                            component: ["x", "y"][c],
                            x: p[0],
                            y: p[1],
                            a: old,
                            b: value,
                        });
                    }
                    Some(_) => {}
                    None => fixed[dof] = Some((value, k)),
                }
            }
        }
        if !matched {
            return Err(FemError::EmptyRegion {
                section: format!("dirichlet #{}", k + 1),
                region: d.region,
                body: scene.bodies[d.body].name.clone(),
                what: "node",
            });
        }
    }
    Ok(fixed.into_iter().map(|f| f.map(|(v, _)| v)).collect())
}

/// Applied nodal forces (tractions and body forces) on all DOFs.
pub fn applied_loads(scene: &Scene, meshes: &[Mesh], dofs: &Dofs) -> Result<Vec<f64>, FemError> {
    let tol = scene.tolerance();
    let t = scene.thickness;
    let mut f = vec![0.0; dofs.len()];
    for (k, nm) in scene.neumann.iter().enumerate() {
        let mesh = &meshes[nm.body];
        let mut matched = false;
        for &[a, b] in &mesh.boundary {
            let (pa, pb) = (mesh.nodes[a], mesh.nodes[b]);
            if !nm.selects_edge(&scene.bodies[nm.body], [a, b], [pa, pb], tol) {
                continue;
            }
            matched = true;
            // The traction is linear along the edge: consistent loads L(2tₐ + t_b)/6, L(tₐ + 2t_b)/6.
            let len = geometry::distance(pa, pb);
            let (ta, tb) = (nm.traction.at(pa), nm.traction.at(pb));
            for c in 0..2 {
                f[dofs.dof(nm.body, a, c)] += t * len * (2.0 * ta[c] + tb[c]) / 6.0;
                f[dofs.dof(nm.body, b, c)] += t * len * (ta[c] + 2.0 * tb[c]) / 6.0;
            }
        }
        if !matched {
            return Err(FemError::EmptyRegion {
                section: format!("neumann #{}", k + 1),
                region: nm.region,
                body: scene.bodies[nm.body].name.clone(),
                what: "edge",
            });
        }
    }
    if let Some(g) = scene.gravity {
        for (b, (mesh, body)) in meshes.iter().zip(&scene.bodies).enumerate() {
            let rho = body.density.unwrap_or(0.0);
            let force = [rho * g[0], rho * g[1]];
            for c in 0..mesh.cells.len() {
                let nodes = mesh.cells.cell(c);
                let fe: Vec<f64> = match &mesh.cells {
                    Cells::Triangles(tr) => {
                        element::p1_body_force(tr[c].map(|n| mesh.nodes[n]), force, t)
                            .iter()
                            .copied()
                            .collect()
                    }
                    Cells::Quads(q) => {
                        element::q1_body_force(q[c].map(|n| mesh.nodes[n]), force, t)
                            .iter()
                            .copied()
                            .collect()
                    }
                };
                for (a, &n) in nodes.iter().enumerate() {
                    f[dofs.dof(b, n, 0)] += fe[2 * a];
                    f[dofs.dof(b, n, 1)] += fe[2 * a + 1];
                }
            }
        }
    }
    Ok(f)
}

/// Stresses (σₓₓ, σᵧᵧ, σₓᵧ, σ_zz) per cell (P1: exact constant; Q1: at the centroid).
pub fn cell_stresses(mesh: &Mesh, material: &Material, displacement: &[[f64; 2]]) -> Vec<[f64; 4]> {
    let d = material.elasticity();
    let finish = |s: nalgebra::SVector<f64, 3>| [s[0], s[1], s[2], material.sigma_zz(s[0], s[1])];
    match &mesh.cells {
        Cells::Triangles(t) => t
            .iter()
            .map(|cell| {
                let p: [Point; 3] = cell.map(|n| mesh.nodes[n]);
                let (b, _) = element::p1_strain(p);
                let u = nalgebra::SVector::<f64, 6>::from_iterator(
                    cell.iter().flat_map(|&n| displacement[n]),
                );
                finish(d * (b * u))
            })
            .collect(),
        Cells::Quads(q) => q
            .iter()
            .map(|cell| {
                let p: [Point; 4] = cell.map(|n| mesh.nodes[n]);
                let (b, _) = element::q1_strain(p, 0.0, 0.0);
                let u = nalgebra::SVector::<f64, 8>::from_iterator(
                    cell.iter().flat_map(|&n| displacement[n]),
                );
                finish(d * (b * u))
            })
            .collect(),
    }
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
