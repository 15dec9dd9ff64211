//! From a scene to the assembled model: meshes, stiffness, loads, supports and contact rows, and
//! the reduced quadratic program on the free DOFs.
//!
//! Only what the scene names is built: no contact pair → no rows and no QP; no gravity → no body
//! force.  Prescribed displacements are eliminated with symmetric lifting, so the reduced
//! stiffness stays symmetric: f̃ = f_F − K_FD u_D and g̃ = g − B_D u_D.

use serde::Serialize;
use sprs::TriMat;

use crate::contact::{self, ContactError, PairRows};
use crate::fem::{self, Dofs, FemError, Material};
use crate::geometry::Point;
use crate::mesh::{self, BodyGeometry, Mesh, MeshError, MeshLimits};
use crate::qp::{CscMatrix, QpError, QpProblem};
use crate::scene::Scene;

/// Something that a scene asks the program to simulate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Effect {
    /// Prescribed displacements.
    Dirichlet,
    /// Surface tractions.
    Neumann,
    /// Body force from `[model] gravity`.
    Gravity,
    /// Contact constraints (a QP instead of one linear solve).
    Contact,
}

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
    /// A body can move rigidly and nothing (no support, no contact) holds it.
    #[error("body \"{body}\" is not held: {modes} rigid-body mode(s) are free and it is in no contact pair; add a [[dirichlet]] support")]
    Unsupported {
        /// Body name.
        body: String,
        /// Number of free rigid-body modes.
        modes: usize,
    },
    /// The reduced QP failed its checks.
    #[error(transparent)]
    Qp(#[from] QpError),
    /// The reduced QP was already moved out of the model.
    #[error("the model's QP was already taken by a solve")]
    QpTaken,
}

/// Meshes every body.  Break points make the mesh exact where it matters: other bodies' corners
/// on this boundary (conforming interfaces) and the crossings of every region box that names the
/// body (supported and loaded lengths exact for every hmax).
pub fn mesh_scene(scene: &Scene, limits: &MeshLimits) -> Result<Vec<Mesh>, ModelError> {
    let tol = scene.tolerance();
    let mut meshes = Vec::with_capacity(scene.bodies.len());
    for (b, body) in scene.bodies.iter().enumerate() {
        let mut breaks: Vec<Point> = scene
            .bodies
            .iter()
            .enumerate()
            .filter(|(o, _)| *o != b)
            .flat_map(|(_, o)| o.polygon.iter().copied())
            .collect();
        let mut regions: Vec<[f64; 4]> = Vec::new();
        regions.extend(
            scene
                .dirichlet
                .iter()
                .filter(|d| d.body == b)
                .map(|d| d.region),
        );
        regions.extend(
            scene
                .neumann
                .iter()
                .filter(|n| n.body == b)
                .map(|n| n.region),
        );
        for r in &regions {
            breaks.extend(mesh::box_crossings(&body.polygon, r, tol));
        }
        // A contact box only selects candidate nodes; a crossing just beside a corner (the thin
        // box's side along a side edge) would force a sliver element, so those are skipped.
        let near_corner = |p: &Point| {
            body.polygon
                .iter()
                .any(|v| crate::geometry::distance(*v, *p) < 0.25 * body.hmax)
        };
        for c in scene.contacts.iter().filter(|c| c.bodies.contains(&b)) {
            if let Some(r) = &c.region {
                breaks.extend(
                    mesh::box_crossings(&body.polygon, r, tol)
                        .into_iter()
                        .filter(|p| !near_corner(p)),
                );
            }
        }
        let geometry = BodyGeometry {
            polygon: &body.polygon,
            hmax: body.hmax,
            element: body.element,
            breakpoints: &breaks,
            tol,
        };
        let m = mesh::mesh_body(&geometry, limits).map_err(|source| ModelError::Mesh {
            body: body.name.clone(),
            source,
        })?;
        meshes.push(m);
    }
    Ok(meshes)
}

/// The assembled model of a scene.
#[derive(Debug, Clone)]
pub struct Model {
    /// Per-body meshes.
    pub meshes: Vec<Mesh>,
    /// Per-body materials.
    pub materials: Vec<Material>,
    /// Global numbering.
    pub dofs: Dofs,
    /// The columns of the full stiffness K at the fixed DOFs (all DOFs × `fixed_dofs`), enough
    /// for the support reactions K_D·u; the rest of K lives on only as the reduced QP.
    pub supports: CscMatrix,
    /// Fixed DOFs in increasing order (the columns of `supports`).
    pub fixed_dofs: Vec<usize>,
    /// Applied nodal forces on all DOFs.
    pub load: Vec<f64>,
    /// Prescribed value of each DOF, `None` for a free DOF.
    pub fixed: Vec<Option<f64>>,
    /// Free DOFs in increasing order (the QP's unknowns).
    pub free: Vec<usize>,
    /// Contact rows per pair.
    pub contacts: Vec<PairRows>,
    /// Contact matrix B on all DOFs (m × DOFs), rows in pair order.
    pub constraints: CscMatrix,
    /// Initial gaps g (length m).
    pub gap: Vec<f64>,
    /// Rigid-body modes left free by the supports, per body (body index, count).
    pub floating: Vec<(usize, usize)>,
    /// Those modes restricted to the free DOFs (a null-space basis of the reduced stiffness).
    pub kernel: Vec<Vec<f64>>,
    /// What was assembled.
    pub effects: Vec<Effect>,
    /// The reduced QP (see [`Model::qp`]); `None` once taken by [`Model::take_qp`].
    reduced: Option<QpProblem>,
}

/// Assembles the model on given meshes.
pub fn assemble(scene: &Scene, meshes: Vec<Mesh>) -> Result<Model, ModelError> {
    let dofs = Dofs::new(&meshes.iter().map(|m| m.nodes.len()).collect::<Vec<_>>());
    let materials: Vec<Material> = scene
        .bodies
        .iter()
        .map(|b| Material {
            young: b.young,
            poisson: b.poisson,
            plane: scene.plane,
        })
        .collect();
    let stiffness = fem::assemble_stiffness(&meshes, &materials, scene.thickness, &dofs);
    let load = fem::applied_loads(scene, &meshes, &dofs)?;
    let fixed = fem::prescribed(scene, &meshes, &dofs)?;
    let free: Vec<usize> = (0..dofs.len()).filter(|d| fixed[*d].is_none()).collect();

    let mut floating = Vec::new();
    let mut kernel = Vec::new();
    for (b, mesh) in meshes.iter().enumerate() {
        let modes = fem::free_rigid_modes(mesh, b, &dofs, &fixed);
        if modes.is_empty() {
            continue;
        }
        if !scene.contacts.iter().any(|c| c.bodies.contains(&b)) {
            return Err(ModelError::Unsupported {
                body: scene.bodies[b].name.clone(),
                modes: modes.len(),
            });
        }
        floating.push((b, modes.len()));
        kernel.extend(
            modes
                .into_iter()
                .map(|m| free.iter().map(|&d| m[d]).collect::<Vec<f64>>()),
        );
    }

    let contacts = contact::contact_rows(scene, &meshes)?;
    let m: usize = contacts.iter().map(|p| p.rows.len()).sum();
    let mut b = TriMat::with_capacity((m, dofs.len()), 6 * m);
    let mut gap = Vec::with_capacity(m);
    let mut row = 0;
    for pair in &contacts {
        for r in &pair.rows {
            let [ma, mb] = r.master_nodes;
            for (c, &nc) in r.normal.iter().enumerate() {
                b.add_triplet(row, dofs.dof(pair.slave, r.slave_node, c), -nc);
                if r.alpha != 0.0 {
                    b.add_triplet(row, dofs.dof(pair.master, ma, c), r.alpha * nc);
                }
                if r.alpha != 1.0 {
                    b.add_triplet(row, dofs.dof(pair.master, mb, c), (1.0 - r.alpha) * nc);
                }
            }
            gap.push(r.gap);
            row += 1;
        }
    }
    let constraints: CscMatrix = b.to_csc();

    let mut effects = Vec::new();
    if !scene.dirichlet.is_empty() {
        effects.push(Effect::Dirichlet);
    }
    if !scene.neumann.is_empty() {
        effects.push(Effect::Neumann);
    }
    if scene.gravity.is_some() {
        effects.push(Effect::Gravity);
    }
    if m > 0 {
        effects.push(Effect::Contact);
    }

    let free_index = free_index(&free, dofs.len());
    let (a, lift_f) = restrict(&stiffness, &fixed, &free_index, true);
    let (b_free, lift_g) = restrict(&constraints, &fixed, &free_index, false);
    let f = free
        .iter()
        .zip(&lift_f)
        .map(|(&d, l)| load[d] - l)
        .collect();
    let g = gap.iter().zip(&lift_g).map(|(g, l)| g - l).collect();
    let reduced = QpProblem::try_new(a, f, b_free, g)?.with_kernel(kernel.clone())?;
    let fixed_dofs: Vec<usize> = (0..dofs.len()).filter(|d| fixed[*d].is_some()).collect();
    let supports = columns(&stiffness, &fixed_dofs);
    drop(stiffness);

    Ok(Model {
        meshes,
        materials,
        dofs,
        supports,
        fixed_dofs,
        load,
        fixed,
        free,
        contacts,
        constraints,
        gap,
        floating,
        kernel,
        effects,
        reduced: Some(reduced),
    })
}

/// Index of each DOF among the free ones (`usize::MAX` for a fixed DOF).
fn free_index(free: &[usize], n: usize) -> Vec<usize> {
    let mut index = vec![usize::MAX; n];
    for (k, &d) in free.iter().enumerate() {
        index[d] = k;
    }
    index
}

/// The listed columns of a CSC matrix, as a new CSC matrix.
fn columns(m: &CscMatrix, list: &[usize]) -> CscMatrix {
    let mut col_ptr = Vec::with_capacity(list.len() + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::new();
    let mut values = Vec::new();
    for &j in list {
        if let Some(col) = m.outer_view(j) {
            for (i, v) in col.iter() {
                row_idx.push(i);
                values.push(*v);
            }
        }
        col_ptr.push(row_idx.len());
    }
    CscMatrix::new_csc((m.rows(), list.len()), col_ptr, row_idx, values)
}

/// Keeps the free columns of a CSC matrix (and the free rows too when `rows_too`), renumbered;
/// returns it with the product of the dropped (fixed) columns with their prescribed values.
fn restrict(
    m: &CscMatrix,
    fixed: &[Option<f64>],
    free_index: &[usize],
    rows_too: bool,
) -> (CscMatrix, Vec<f64>) {
    let n_free = free_index.iter().filter(|i| **i != usize::MAX).count();
    let n_rows = if rows_too { n_free } else { m.rows() };
    let mut col_ptr = Vec::with_capacity(n_free + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::with_capacity(m.nnz());
    let mut values = Vec::with_capacity(m.nnz());
    let mut lifted = vec![0.0; n_rows];
    for (j, col) in m.outer_iterator().enumerate() {
        match fixed[j] {
            None => {
                for (i, v) in col.iter() {
                    let r = if rows_too { free_index[i] } else { i };
                    if r != usize::MAX {
                        row_idx.push(r);
                        values.push(*v);
                    }
                }
                col_ptr.push(row_idx.len());
            }
            Some(u) if u != 0.0 => {
                for (i, v) in col.iter() {
                    let r = if rows_too { free_index[i] } else { i };
                    if r != usize::MAX {
                        lifted[r] += v * u;
                    }
                }
            }
            Some(_) => {}
        }
    }
    (
        CscMatrix::new_csc((n_rows, n_free), col_ptr, row_idx, values),
        lifted,
    )
}

impl Model {
    /// Number of contact rows m.
    pub fn rows(&self) -> usize {
        self.gap.len()
    }

    /// Index of each DOF among the free ones (`usize::MAX` for a fixed DOF).
    pub fn free_index(&self) -> Vec<usize> {
        free_index(&self.free, self.dofs.len())
    }

    /// A copy of the reduced QP: A = K_FF, f = f_F − K_FD u_D, B = B_F, g = g − B_D u_D, with
    /// the known null space of A attached.  Solvers use [`Model::take_qp`] to avoid the copy.
    pub fn qp(&self) -> Result<QpProblem, ModelError> {
        self.reduced.clone().ok_or(ModelError::QpTaken)
    }

    /// Moves the reduced QP out of the model (one copy of A in memory); later calls fail.
    pub fn take_qp(&mut self) -> Result<QpProblem, ModelError> {
        self.reduced.take().ok_or(ModelError::QpTaken)
    }

    /// Support reactions K_D·u at the fixed DOFs (in `fixed_dofs` order), internal force only.
    pub fn support_forces(&self, u: &[f64]) -> Vec<f64> {
        crate::qp::mat_t_vec(&self.supports, u)
    }

    /// Full displacement vector from the free unknowns and the prescribed values.
    pub fn expand(&self, x: &[f64]) -> Vec<f64> {
        let mut u: Vec<f64> = self.fixed.iter().map(|f| f.unwrap_or(0.0)).collect();
        for (&d, v) in self.free.iter().zip(x) {
            u[d] = *v;
        }
        u
    }

    /// Nodal displacements of body `b` from the full vector.
    pub fn body_displacements(&self, b: usize, u: &[f64]) -> Vec<[f64; 2]> {
        self.dofs
            .body_range(b)
            .step_by(2)
            .map(|d| [u[d], u[d + 1]])
            .collect()
    }
}
