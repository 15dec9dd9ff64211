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

use serde::Serialize;
use sprs::TriMat;

use crate::contact::{ContactError, ContactRow, PairRows};
use crate::effects::{ContactEffect, Discretisation, EffectError, Effects, ModelParts};
use crate::fem::{self, Dofs, FemError, Material};
use crate::geometry::Point;
use crate::mesh::{self, BodyGeometry, Mesh, MeshError, MeshLimits};
use crate::qp::{CscMatrix, QpError, QpProblem};
use crate::scene::Scene;

pub use crate::effects::Effect;

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

/// Why a contact pair produced no constraint row.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum NoRowReason {
    /// No boundary node of either body is within one element size of the other (no region box).
    NoCandidates,
    /// Candidate slave nodes exist, but no master segment faces any of them.
    NoFacingSegment,
    /// Every row was inert (all its DOFs prescribed) and was removed.
    AllInert,
}

/// Something assembly had to approximate or leave out, counted per contact pair.  `pair` is the
/// 1-based index of the `[[contact]]` section; bodies are named.  [`std::fmt::Display`] gives a
/// one-line message; serialised (JSON) with the variant name in `kind`.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ModelWarning {
    /// The pair produced no constraint row at all (it has no effect on the solution).
    NoContactRow {
        /// 1-based pair index.
        pair: usize,
        /// The pair's two bodies, as in the scene.
        bodies: [String; 2],
        /// Why.
        reason: NoRowReason,
    },
    /// Slave candidate nodes that got no row: node-to-segment, no facing master segment (within
    /// its span, on its outer side); mortar, less than a quarter of the node's share of the slave
    /// interface is covered by the master (the ends of the contact zone).  Nothing keeps these
    /// nodes themselves out of the master.
    UnmatchedNodes {
        /// 1-based pair index.
        pair: usize,
        /// Slave body.
        slave: String,
        /// Master body.
        master: String,
        /// Nodes without a row.
        nodes: usize,
        /// All slave candidate nodes of the pair.
        candidates: usize,
    },
    /// Rows whose tributary length (for the pressure λ / length) does not come from slave edges
    /// facing the master: it falls back to other interface edges, to any adjacent boundary edge,
    /// or (`unit_length` of them) to 1.0.
    TributaryFallback {
        /// 1-based pair index.
        pair: usize,
        /// Slave body.
        slave: String,
        /// Master body.
        master: String,
        /// Rows with a fallback length.
        rows: usize,
        /// Of those, rows given the length 1.0 (no adjacent boundary edge of positive length).
        unit_length: usize,
    },
    /// The bodies overlap at the start (by less than the pair's larger `hmax`): the slave nodes
    /// inside the master have rows with negative gaps, which push them out.
    InitialOverlap {
        /// 1-based pair index.
        pair: usize,
        /// Slave body.
        slave: String,
        /// Master body.
        master: String,
        /// Slave nodes starting inside the master, each with a row (negative gap).
        nodes: usize,
        /// Master boundary nodes starting inside the slave (not constrained by node-to-segment
        /// rows).
        master_nodes: usize,
        /// Body of the deepest node.
        deepest_body: String,
        /// Position of the deepest node (undeformed).
        deepest: Point,
        /// Its depth inside the other body.
        depth: f64,
    },
    /// Rows whose every DOF is prescribed on both sides: they constrain nothing a solver can
    /// change and were removed from B and g (their reduced gap is ≥ 0).
    InertRows {
        /// 1-based pair index.
        pair: usize,
        /// Slave body.
        slave: String,
        /// Master body.
        master: String,
        /// Rows removed.
        rows: usize,
        /// Slave node position of the first one.
        first: Point,
    },
}

impl ModelWarning {
    /// The variant's name as serialised in `kind`.
    pub fn kind(&self) -> &'static str {
        match self {
            ModelWarning::NoContactRow { .. } => "no_contact_row",
            ModelWarning::UnmatchedNodes { .. } => "unmatched_nodes",
            ModelWarning::TributaryFallback { .. } => "tributary_fallback",
            ModelWarning::InitialOverlap { .. } => "initial_overlap",
            ModelWarning::InertRows { .. } => "inert_rows",
        }
    }

    /// The 1-based contact pair the warning is about.
    pub fn pair(&self) -> usize {
        match self {
            ModelWarning::NoContactRow { pair, .. }
            | ModelWarning::UnmatchedNodes { pair, .. }
            | ModelWarning::TributaryFallback { pair, .. }
            | ModelWarning::InitialOverlap { pair, .. }
            | ModelWarning::InertRows { pair, .. } => *pair,
        }
    }
}

impl std::fmt::Display for ModelWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ModelWarning::NoContactRow {
                pair,
                bodies,
                reason,
            } => {
                write!(
                    f,
                    "contact #{pair} (\"{}\" – \"{}\") gave no constraint row: ",
                    bodies[0], bodies[1]
                )?;
                match reason {
                    NoRowReason::NoCandidates => write!(
                        f,
                        "no boundary node of either body is within one element size of the other (give the pair a region box if they are meant to touch)"
                    ),
                    NoRowReason::NoFacingSegment => write!(
                        f,
                        "no master segment faces any candidate slave node (check the region box and the bodies' positions)"
                    ),
                    NoRowReason::AllInert => write!(
                        f,
                        "every row had all its DOFs prescribed on both sides and was removed as inert"
                    ),
                }
            }
            ModelWarning::UnmatchedNodes {
                pair,
                slave,
                master,
                nodes,
                candidates,
            } => write!(
                f,
                "contact #{pair}: {nodes} of {candidates} candidate node(s) of slave \"{slave}\" face no segment of master \"{master}\" (mortar: the master covers less than a quarter of their share of the interface) and have no constraint row"
            ),
            ModelWarning::TributaryFallback {
                pair,
                slave,
                master,
                rows,
                unit_length,
            } => {
                write!(
                    f,
                    "contact #{pair} (slave \"{slave}\", master \"{master}\"): {rows} row(s) have no slave edge facing the master; their pressure uses the length of other adjacent edges"
                )?;
                if *unit_length > 0 {
                    write!(f, " ({unit_length} with no edge at all: length 1.0)")?;
                }
                Ok(())
            }
            ModelWarning::InitialOverlap {
                pair,
                slave,
                master,
                nodes,
                master_nodes,
                deepest_body,
                deepest,
                depth,
            } => {
                write!(
                    f,
                    "contact #{pair}: bodies \"{slave}\" (slave) and \"{master}\" (master) overlap at the start, deepest {depth:e} at ({}, {}) of \"{deepest_body}\"; {nodes} slave node(s) start inside the master and are pushed out by rows with negative gaps",
                    deepest[0], deepest[1]
                )?;
                if *master_nodes > 0 {
                    write!(f, ", {master_nodes} master node(s) start inside the slave")?;
                }
                Ok(())
            }
            ModelWarning::InertRows {
                pair,
                slave,
                master,
                rows,
                first,
            } => write!(
                f,
                "contact #{pair} (slave \"{slave}\", master \"{master}\"): {rows} row(s) have every DOF fixed by [[dirichlet]] on both sides (first at ({}, {})) and were removed as inert",
                first[0], first[1]
            ),
        }
    }
}

/// Meshes every body.  Break points make the mesh exact where it matters: other bodies' corners
/// on this boundary (conforming interfaces), the crossings of every region box that names the
/// body (supported and loaded lengths exact for every hmax) and those of the body's
/// `[[body.refine]]` boxes.
pub fn mesh_scene(scene: &Scene, limits: &MeshLimits) -> Result<Vec<Mesh>, ModelError> {
    let tol = scene.tolerance();
    let mut meshes = Vec::with_capacity(scene.bodies.len());
    for (b, body) in scene.bodies.iter().enumerate() {
        // A Gmsh body brings its mesh: nothing to mesh, no break points (its groups select
        // nodes and edges exactly).
        if let Some(imported) = &body.imported {
            let cells = imported.mesh.cells.len();
            if cells > limits.max_elements {
                return Err(ModelError::Mesh {
                    body: body.name.clone(),
                    source: mesh::MeshError::TooManyElements {
                        estimated: cells,
                        limit: limits.max_elements,
                    },
                });
            }
            meshes.push(imported.mesh.clone());
            continue;
        }
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
        // Refined regions' crossings too, so the fine zone starts and ends at a node (and two
        // bodies with the same refine boxes break their shared edges at the same points).  A
        // crossing closer than half the region's size to a vertex would only make a short edge
        // (a sliver) next to a node that is exact already: skipped.  Any body's vertex counts,
        // so that two bodies sharing an edge skip the same crossings and stay conforming.
        for r in &body.refine {
            breaks.extend(
                mesh::box_crossings(&body.polygon, &r.region, tol)
                    .into_iter()
                    .filter(|p| {
                        scene
                            .bodies
                            .iter()
                            .flat_map(|o| o.polygon.iter())
                            .all(|v| crate::geometry::distance(*v, *p) >= 0.5 * r.hmax)
                    }),
            );
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
                let crossings = mesh::box_crossings(&body.polygon, r, tol);
                let holds_vertex = body
                    .polygon
                    .iter()
                    .any(|v| crate::geometry::in_box(*v, r, tol));
                let kept: Vec<Point> = crossings
                    .iter()
                    .copied()
                    .filter(|p| !near_corner(p))
                    .collect();
                // A box that meets the boundary only next to a corner (and holds no vertex)
                // would otherwise hold no mesh node: keep its crossings, sliver or not, so that
                // "the box meets the boundary" (checked at validation) always gives a node.
                if kept.is_empty() && !holds_vertex {
                    breaks.extend(crossings);
                } else {
                    breaks.extend(kept);
                }
            }
        }
        let geometry = BodyGeometry {
            polygon: &body.polygon,
            hmax: body.hmax,
            element: body.element,
            breakpoints: &breaks,
            refine: &body.refine,
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
        .map(|b| Material {
            young: b.young,
            poisson: b.poisson,
            plane: scene.plane,
        })
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
    let fixed = parts.prescribed();
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
    let (constraints, gap) = contact_matrix(&contacts, &dofs);
    let mut named: Vec<Effect> = contributions.iter().map(|c| c.effect()).collect();
    named.retain(|e| *e != Effect::Contact || !gap.is_empty());
    named.sort_by_key(|e| *e as u8);

    let free_index = free_index(&free, dofs.len());
    let (a, lift_f) = restrict(&stiffness, &fixed, &free_index, true);
    let (b_free, lift_g) = restrict(&constraints, &fixed, &free_index, false);
    let load = parts.load;
    let f: Vec<f64> = free
        .iter()
        .zip(&lift_f)
        .map(|(&d, l)| load[d] - l)
        .collect();
    let g: Vec<f64> = gap.iter().zip(&lift_g).map(|(g, l)| g - l).collect();
    check_finite(a.data(), &f, &g)?;
    let reduced = QpProblem::try_new(a, f, b_free, g)?.with_kernel(kernel.clone())?;
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
        floating,
        kernel,
        effects: named,
        warnings,
    };
    Ok(Assembly { model, qp: reduced })
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

/// The contact matrix B on all DOFs (rows in pair order) and the initial gaps g.
fn contact_matrix(contacts: &[PairRows], dofs: &Dofs) -> (CscMatrix, Vec<f64>) {
    let m: usize = contacts.iter().map(|p| p.rows.len()).sum();
    let mut b = TriMat::with_capacity((m, dofs.len()), 6 * m);
    let mut gap = Vec::with_capacity(m);
    for (row, (pair, r)) in contacts
        .iter()
        .flat_map(|pair| pair.rows.iter().map(move |r| (pair, r)))
        .enumerate()
    {
        for (d, v) in row_entries(dofs, pair, r) {
            b.add_triplet(row, d, v);
        }
        gap.push(r.gap);
    }
    (b.to_csc(), gap)
}

/// The entries (DOF, coefficient) of a contact row of B, in the order B stores them: for each
/// component c, the slave node's −n_c, then w_k n_c on each master node k with a non-zero weight.
fn row_entries(dofs: &Dofs, pair: &PairRows, r: &ContactRow) -> Vec<(usize, f64)> {
    let mut entries = Vec::with_capacity(2 + 2 * r.masters.len());
    for (c, &nc) in r.normal.iter().enumerate() {
        entries.push((dofs.dof(pair.slave, r.slave_node, c), -nc));
        for &(k, w) in &r.masters {
            if w != 0.0 {
                entries.push((dofs.dof(pair.master, k, c), w * nc));
            }
        }
    }
    entries
}

/// Removes a pair's inert rows (every DOF with a non-zero coefficient prescribed) and returns
/// the pair's warnings; refuses an inert row whose reduced gap g − B_D u_D is below −tolerance.
fn screen_pair(
    contact: &ContactEffect<'_>,
    dofs: &Dofs,
    fixed: &[Option<f64>],
    pair: &mut PairRows,
) -> Result<Vec<ModelWarning>, ModelError> {
    let tol = contact.tol;
    let interface = &contact.interfaces[pair.pair];
    let name = |b: usize| interface.side(b).name.to_string();
    let number = pair.pair + 1;
    let mut warnings = Vec::new();
    let mut inert = 0;
    let mut first = None;
    let mut kept = Vec::with_capacity(pair.rows.len());
    for r in std::mem::take(&mut pair.rows) {
        let entries = row_entries(dofs, pair, &r);
        let mut lifted = 0.0;
        let mut all_fixed = true;
        for &(d, v) in entries.iter().filter(|(_, v)| *v != 0.0) {
            match fixed[d] {
                Some(u) => lifted += v * u,
                None => all_fixed = false,
            }
        }
        if !all_fixed {
            kept.push(r);
            continue;
        }
        let reduced = r.gap - lifted;
        if reduced < -tol {
            return Err(ModelError::PrescribedPenetration {
                pair: number,
                slave: name(pair.slave),
                master: name(pair.master),
                point: r.position,
                gap: reduced,
            });
        }
        inert += 1;
        first.get_or_insert(r.position);
    }
    pair.rows = kept;
    let (slave, master) = (name(pair.slave), name(pair.master));
    if let Some(o) = &pair.overlap {
        warnings.push(ModelWarning::InitialOverlap {
            pair: number,
            slave: slave.clone(),
            master: master.clone(),
            nodes: o.slave_nodes,
            master_nodes: o.master_nodes,
            deepest_body: name(o.deepest_body),
            deepest: o.deepest,
            depth: o.depth,
        });
    }
    if pair.unmatched > 0 && pair.unmatched < pair.candidates {
        warnings.push(ModelWarning::UnmatchedNodes {
            pair: number,
            slave: slave.clone(),
            master: master.clone(),
            nodes: pair.unmatched,
            candidates: pair.candidates,
        });
    }
    if pair.tributary_fallbacks > 0 {
        warnings.push(ModelWarning::TributaryFallback {
            pair: number,
            slave: slave.clone(),
            master: master.clone(),
            rows: pair.tributary_fallbacks,
            unit_length: pair.unit_tributaries,
        });
    }
    if let Some(first) = first {
        warnings.push(ModelWarning::InertRows {
            pair: number,
            slave: slave.clone(),
            master: master.clone(),
            rows: inert,
            first,
        });
    }
    if pair.rows.is_empty() {
        let reason = if inert > 0 {
            NoRowReason::AllInert
        } else if pair.candidates == 0 {
            NoRowReason::NoCandidates
        } else {
            NoRowReason::NoFacingSegment
        };
        let [k, l] = interface.sides.map(|s| s.body);
        warnings.push(ModelWarning::NoContactRow {
            pair: number,
            bodies: [name(k), name(l)],
            reason,
        });
    }
    Ok(warnings)
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

/// Refuses a reduced stiffness, load or gap that overflowed, naming the scene keys behind it:
/// the material (`young`, `poisson`: the bulk modulus E / (1 − 2ν)(1 + ν)) for A; the lifting
/// K_FD u_D (`young` × [[dirichlet]] `value`) or the applied loads ([[neumann]] `traction`,
/// `gravity`) for f; the lifting B_D u_D ([[dirichlet]] `value`) for g.
fn check_finite(stiffness: &[f64], load: &[f64], gap: &[f64]) -> Result<(), ModelError> {
    if stiffness.iter().any(|v| !v.is_finite()) {
        return Err(ModelError::Overflow {
            what: "the stiffness",
            cause: "a body's `young` divided by (1 − 2·`poisson`)(1 + `poisson`), times the element's shape terms",
        });
    }
    if load.iter().any(|v| !v.is_finite()) {
        return Err(ModelError::Overflow {
            what: "the load after lifting the prescribed displacements",
            cause: "the stiffness (`young`) times a prescribed displacement ([[dirichlet]] `value`), or a load ([[neumann]] `traction`, `gravity`) summed over the body",
        });
    }
    if gap.iter().any(|v| !v.is_finite()) {
        return Err(ModelError::Overflow {
            what: "a contact gap after lifting the prescribed displacements",
            cause: "a prescribed displacement ([[dirichlet]] `value`)",
        });
    }
    Ok(())
}
