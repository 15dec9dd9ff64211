//! From a scene to the assembled model: meshes, stiffness, loads, supports and contact rows, and
//! the reduced quadratic program on the free DOFs, returned side by side ([`Assembly`]): the
//! report needs the model, the solve needs (and owns) the QP.
//!
//! Only what the scene names is built: no contact pair → no rows and no QP; no gravity → no body
//! force.  Prescribed displacements are eliminated with symmetric lifting, so the reduced
//! stiffness stays symmetric: f̃ = f_F − K_FD u_D and g̃ = g − B_D u_D.
//!
//! Assembly refuses what no backend could solve meaningfully and records, as counted
//! [`ModelWarning`]s, what it had to approximate:
//!
//! * contact rows whose every DOF (with a non-zero coefficient) is prescribed constrain nothing:
//!   they are removed from B and g before any backend runs ([`ModelWarning::InertRows`]), unless
//!   their reduced gap g − B_D u_D is negative — then the prescribed displacements themselves
//!   interpenetrate and the scene is refused ([`ModelError::PrescribedPenetration`]);
//! * a body whose rigid-body modes are free and that no remaining contact row touches (on a free
//!   DOF) is refused ([`ModelError::NotHeld`]) — at assembly, so `check` refuses it too;
//! * pairs with no row, slave nodes with no facing master segment, tributary-length fallbacks and
//!   initial overlaps (see [`crate::contact`]) become warnings.

mod error;
mod friction;
mod meshing;
mod path;
mod reduce;
mod rows;
mod screen;
mod warnings;

use crate::contact::PairRows;
use crate::effects::{Discretisation, Effects, ModelParts};
use crate::fem::{self, Dofs, Material};
use crate::mesh::Mesh;
use crate::qp::{ConstraintBlock, CscMatrix, QpProblem};
use crate::scene::Scene;
use reduce::{check_finite, columns, free_index, restrict};
use rows::{contact_matrix, row_entries};
use screen::screen_pair;

pub use crate::effects::Effect;
pub use error::ModelError;
pub use friction::TangentialRow;
pub use meshing::mesh_scene;
pub use path::{increments, Increment, LoadGroup, LoadPath};
pub use warnings::{FreeMotion, ModelWarning, NoRowReason};

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
    /// Contact matrix B on all DOFs (m × DOFs): the normal rows in pair order, then the
    /// tangential rows of frictional pairs (`tangential`, in the same order).
    pub constraints: CscMatrix,
    /// Initial gaps g (length m; 0 on tangential rows).
    pub gap: Vec<f64>,
    /// The tangential rows of the frictional pairs (empty without friction): the last
    /// `tangential.len()` rows of B, one box block in the QP.
    pub tangential: Vec<TangentialRow>,
    /// The load path of a scene with `[[step]]` (`None`: one step at full load); the model's
    /// `load` and `fixed` values are those of its last increment.
    pub path: Option<LoadPath>,
    /// Rigid-body modes left free by the supports, per body (body index, count).
    pub floating: Vec<(usize, usize)>,
    /// Those modes restricted to the free DOFs (a null-space basis of the reduced stiffness).
    pub kernel: Vec<Vec<f64>>,
    /// What was assembled.
    pub effects: Vec<Effect>,
    /// What assembly approximated or left out (inert rows removed, unmatched nodes, fallbacks,
    /// initial overlaps, pairs without rows), in pair order.
    pub warnings: Vec<ModelWarning>,
}

/// What assembly produces: the model (meshes, numbering, supports, contact rows — what the report
/// and the output files need) and the reduced QP (what a solve needs), as two values so that each
/// consumer takes its own and the solve can own the only copy of A.
#[derive(Debug, Clone)]
pub struct Assembly {
    /// Everything but the QP.
    pub model: Model,
    /// The reduced QP: A = K_FF, f = f_F − K_FD u_D, B = B_F, g = g − B_D u_D, with the known
    /// null space of A attached.
    pub qp: QpProblem,
}

/// Assembles the model on given meshes: the stiffness, then every effect the scene names
/// ([`Effects`]), then the reduced QP.
pub fn assemble(scene: &Scene, meshes: Vec<Mesh>) -> Result<Assembly, ModelError> {
    let dofs = Dofs::new(&meshes.iter().map(|m| m.nodes.len()).collect::<Vec<_>>());
    let materials: Vec<Material> = scene
        .bodies
        .iter()
        .map(|b| Material::of_body(b, scene.plane))
        .collect();
    let stiffness = fem::assemble_stiffness(&meshes, &materials, scene.thickness, &dofs);
    let effects = Effects::of(scene);
    let on = Discretisation {
        meshes: &meshes,
        dofs: &dofs,
    };
    let mut parts = ModelParts::empty(dofs.len());
    let contributions = effects.contributions();
    for c in contributions.iter().filter(|c| !c.after_supports()) {
        c.contribute(on, &mut parts)?;
    }
    let path = LoadPath::of(scene, &effects, on, &parts.fixed)?;
    let mut fixed = parts.prescribed();
    if let Some(path) = &path {
        // Assembled at the path's end: the report describes the last increment.
        let values = path.prescribed_at(path.final_factors());
        for (f, v) in fixed.iter_mut().flatten().zip(values) {
            *f = v;
        }
    }
    let free: Vec<usize> = (0..dofs.len()).filter(|d| fixed[*d].is_none()).collect();
    let (floating, kernel) = free_modes(scene, &effects, &meshes, &dofs, &fixed, &free)?;
    for c in contributions.iter().filter(|c| c.after_supports()) {
        c.contribute(on, &mut parts)?;
    }
    let mut warnings = Vec::new();
    let mut contacts = std::mem::take(&mut parts.pairs);
    if let Some(contact) = &effects.contact {
        for pair in &mut contacts {
            warnings.extend(screen_pair(contact, &dofs, &fixed, pair)?);
        }
    }
    check_held(scene, &floating, &contacts, &dofs, &fixed)?;
    let tangential = friction::tangential_rows(&contacts);
    let (constraints, gap) = contact_matrix(&contacts, &tangential, &dofs);
    let mut named: Vec<Effect> = contributions.iter().map(|c| c.effect()).collect();
    named.retain(|e| *e != Effect::Contact || !gap.is_empty());
    named.sort_by_key(|e| *e as u8);

    let free_index = free_index(&free, dofs.len());
    let (a, lift_f) = restrict(&stiffness, &fixed, &free_index, true);
    let (b_free, lift_g) = restrict(&constraints, &fixed, &free_index, false);
    let load = match &path {
        Some(path) => path.load_at(path.final_factors()),
        None => parts.load,
    };
    let f: Vec<f64> = free
        .iter()
        .zip(&lift_f)
        .map(|(&d, l)| load[d] - l)
        .collect();
    let g: Vec<f64> = gap.iter().zip(&lift_g).map(|(g, l)| g - l).collect();
    check_finite(a.data(), &f, &g)?;
    let reduced = QpProblem::try_new(a, f, b_free, g)?
        .with_kernel(kernel.clone())?
        .with_blocks(constraint_blocks(gap.len(), &tangential))?;
    let fixed_dofs: Vec<usize> = (0..dofs.len()).filter(|d| fixed[*d].is_some()).collect();
    let supports = columns(&stiffness, &fixed_dofs);
    drop(stiffness);

    let model = Model {
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
        tangential,
        path,
        floating,
        kernel,
        effects: named,
        warnings,
    };
    Ok(Assembly { model, qp: reduced })
}

/// The QP's constraint blocks: the normal rows (non-negative), then the tangential rows as one
/// box block, bounded by Tresca's fixed bound or, for Coulomb, 0 — the frictionless start of the
/// fixed point (`crate::friction`), which sets μ λₙ from each solve.
fn constraint_blocks(rows: usize, tangential: &[TangentialRow]) -> Vec<ConstraintBlock> {
    let normal = rows - tangential.len();
    let mut blocks = vec![ConstraintBlock::NonNegative { rows: normal }];
    if !tangential.is_empty() {
        blocks.push(ConstraintBlock::Box {
            bounds: tangential.iter().map(|t| t.bound(0.0)).collect(),
        });
    }
    blocks
}

/// Per floating body (body, count of free modes), and those modes on the free DOFs.
type FreeModes = (Vec<(usize, usize)>, Vec<Vec<f64>>);

/// The rigid-body modes the supports leave free, per body (body, count), and those modes on the
/// free DOFs (a null-space basis of the reduced stiffness); refuses a body with free modes that
/// no contact pair could hold.
fn free_modes(
    scene: &Scene,
    effects: &Effects<'_>,
    meshes: &[Mesh],
    dofs: &Dofs,
    fixed: &[Option<f64>],
    free: &[usize],
) -> Result<FreeModes, ModelError> {
    let mut floating = Vec::new();
    let mut kernel = Vec::new();
    for (b, mesh) in meshes.iter().enumerate() {
        let modes = fem::free_rigid_modes(mesh, b, dofs, fixed);
        if modes.is_empty() {
            continue;
        }
        if !effects.in_contact(b) {
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
    Ok((floating, kernel))
}

/// Refuses a floating body (free rigid modes) on which no remaining contact row acts through a
/// free DOF: nothing holds it.
fn check_held(
    scene: &Scene,
    floating: &[(usize, usize)],
    contacts: &[PairRows],
    dofs: &Dofs,
    fixed: &[Option<f64>],
) -> Result<(), ModelError> {
    for &(b, modes) in floating {
        let range = dofs.body_range(b);
        let held = contacts.iter().any(|pair| {
            pair.rows.iter().any(|r| {
                row_entries(dofs, pair, r)
                    .iter()
                    .any(|&(d, v)| v != 0.0 && range.contains(&d) && fixed[d].is_none())
            })
        });
        if !held {
            let name = |i: usize| &scene.bodies[i].name;
            let pairs: Vec<String> = scene
                .contacts
                .iter()
                .enumerate()
                .filter(|(_, c)| c.bodies.contains(&b))
                .map(|(p, c)| {
                    format!(
                        "#{} (\"{}\" – \"{}\")",
                        p + 1,
                        name(c.bodies[0]),
                        name(c.bodies[1])
                    )
                })
                .collect();
            return Err(ModelError::NotHeld {
                body: name(b).clone(),
                modes,
                pairs: pairs.join(", "),
            });
        }
    }
    Ok(())
}

impl Model {
    /// Number of contact rows m (normal and tangential).
    pub fn rows(&self) -> usize {
        self.gap.len()
    }

    /// The number of normal contact rows (the first rows of B).
    pub fn normal_rows(&self) -> usize {
        self.gap.len() - self.tangential.len()
    }

    /// Index of each DOF among the free ones (`usize::MAX` for a fixed DOF).
    pub fn free_index(&self) -> Vec<usize> {
        free_index(&self.free, self.dofs.len())
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
