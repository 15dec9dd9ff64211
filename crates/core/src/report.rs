//! The result of a run: full displacements, reactions, stresses, contact pressures and probes, as
//! the `result.json` of `docs/scene.md`.

use schemars::JsonSchema;
use serde::Serialize;

pub mod arc;
pub mod balance;

pub use arc::{interface_arc, ArcPosition};
pub use balance::{force_balance, BodyBalance, ForceBalance};

use crate::fem::{self, element};
use crate::geometry::Point;
use crate::mesh::{Cells, Mesh};
use crate::model::{Effect, Model, ModelWarning};
use crate::qp::{mat_vec, KktResiduals};
use crate::scene::{Formulation, Scene};
use crate::solve::Solution;

/// Wall-clock time of each phase, in seconds.
#[derive(Debug, Clone, Copy, Default, Serialize, JsonSchema)]
pub struct Timings {
    /// Meshing.
    pub mesh: f64,
    /// Assembly of stiffness, loads, supports and contact rows.
    pub assemble: f64,
    /// The solve (backend or direct).
    pub solve: f64,
    /// From the start of meshing (the element estimate) to the output fields (stresses,
    /// pressures): reading the scene, building the report and writing the files are not
    /// included (the report cannot contain the time of its own writing).
    pub total: f64,
}

/// Per-body results.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct BodyReport {
    /// Body name.
    pub name: String,
    /// Node count.
    pub nodes: usize,
    /// Element count.
    pub elements: usize,
    /// Largest nodal displacement magnitude.
    pub max_displacement: f64,
    /// Sum of the support reactions on the body `[Rx, Ry]`, from the Dirichlet rows of the
    /// unconstrained stiffness (see [`balance`]).
    pub reaction: [f64; 2],
    /// The applied loads `[Fx, Fy]`, integrated analytically from the scene's tractions and
    /// gravity (see [`balance`]).
    pub applied: [f64; 2],
    /// Resultant of the contact forces acting on the body `[Cx, Cy]`, −Bᵀλ.
    pub contact_force: [f64; 2],
    /// Largest von Mises stress over the body's elements.
    pub max_von_mises: f64,
}

/// One slave node of a contact pair.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct ContactNodeReport {
    /// Slave node x.
    pub x: f64,
    /// Slave node y.
    pub y: f64,
    /// Final normal gap g − (Bu)ᵢ (≥ 0 up to tolerance).
    pub gap: f64,
    /// Initial normal gap.
    pub initial_gap: f64,
    /// Contact force λ at the node (≥ 0, per unit thickness).
    pub multiplier: f64,
    /// The contact pressure λ / `weight` (force per unit thickness per unit length: a stress).
    pub pressure: f64,
    /// Whether the row counts as in contact ([`is_active`]); the VTU's pressure, the SVG's
    /// contact edges and `pressure.svg`'s filled markers use the same test.
    pub active: bool,
    /// The length the multiplier is divided by to give `pressure` (the row's
    /// [`tributary`](crate::contact::ContactRow::tributary)): node-to-segment, the node's
    /// tributary length on the slave interface (half of each adjacent slave edge facing the
    /// master); mortar, D_jj = ∫N_j over the part of the slave interface the master covers.
    pub weight: f64,
    /// Arc-length coordinate of the node along the pair's slave interface, in the scene's length
    /// unit (see [`arc`] for its origin, direction and how disjoint pieces are laid end to end).
    pub s: f64,
    /// The interface piece the node lies on (0-based, in the order of [`arc`]; one piece for a
    /// connected interface).
    pub piece: usize,
}

/// One contact pair.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct ContactReport {
    /// The pair's body names, as in the scene.
    pub bodies: [String; 2],
    /// Slave body name.
    pub slave: String,
    /// How the pair's rows were built (`"node-to-segment"` or `"mortar"`).
    pub formulation: Formulation,
    /// True when slave and master interface nodes coincide.
    pub conforming: bool,
    /// Number of rows.
    pub constraints: usize,
    /// Rows with a positive multiplier (see [`is_active`]).
    pub active: usize,
    /// Sum of the multipliers: the total normal force transmitted.
    pub normal_force: f64,
    /// Per slave node, one per row, in row order (the order of the slave node indices, not
    /// along the interface: sort by `piece`, then `s`, to walk along it).
    pub nodes: Vec<ContactNodeReport>,
}

/// A probe's displacement.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct ProbeReport {
    /// Probe name.
    pub name: String,
    /// Body name.
    pub body: String,
    /// The probed point.
    pub point: Point,
    /// Interpolated displacement `[ux, uy]`.
    pub displacement: [f64; 2],
}

/// `result.json`.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct RunReport {
    /// Scene title.
    pub scene: String,
    /// Backend name (`"cholesky"` when there was no contact row).
    pub backend: String,
    /// `"solved"` only when the residuals meet the tolerance.
    #[schemars(with = "crate::qp::QpStatus")]
    pub status: String,
    /// The tolerance requested.
    pub tolerance: f64,
    /// What was assembled.
    pub effects: Vec<Effect>,
    /// Free DOFs (the QP's unknowns).
    pub dofs: usize,
    /// Contact rows.
    pub constraints: usize,
    /// Active contact rows.
    pub active_constraints: usize,
    /// Backend iterations.
    pub iterations: usize,
    /// ½uᵀAu − fᵀu on the free DOFs.
    pub objective: f64,
    /// Core-computed KKT residuals.
    pub residuals: KktResiduals,
    /// Phase times.
    pub timing_s: Timings,
    /// Per body.
    pub bodies: Vec<BodyReport>,
    /// Per contact pair.
    pub contacts: Vec<ContactReport>,
    /// Per probe.
    pub probes: Vec<ProbeReport>,
    /// Relative force balance: the largest |applied + reaction + contact| over bodies and
    /// components, divided by the largest of those three figures (see [`balance`] for why this is
    /// a real check: it is the summed equilibrium residual of the free DOFs, not zero by
    /// construction).
    pub force_balance: f64,
    /// The backend's note, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub message: Option<String>,
    /// The backend's own verdict before the core's residual check (`status` is the program's).
    #[schemars(with = "crate::qp::QpStatus")]
    pub backend_status: String,
    /// What the program noticed and worked around (empty when nothing).
    pub warnings: Vec<WarningReport>,
    /// `--backend auto` only: every backend the chain ran, in order (absent otherwise).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub attempts: Vec<AttemptReport>,
    /// `--backend auto` only: the backend whose answer is written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chosen: Option<String>,
    /// `--backend auto` only: why the chain had its order, and how it ended.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Where the result comes from: program, scene file, backend settings, machine (written by
    /// `signorini solve`; absent from reports built without it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub provenance: Option<Provenance>,
}

/// What a result can be traced to (`result.json`'s `provenance`).
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct Provenance {
    /// The program's version (`signorini --version`, the crate version).
    pub version: String,
    /// The git commit the program was built from, when the build recorded one (the
    /// `SIGNORINI_COMMIT` environment variable at build time); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub commit: Option<String>,
    /// The scene file as given on the command line; absent for the built-in default scene.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scene_path: Option<String>,
    /// SHA-256 of the scene file's bytes (of the built-in scene's text when no file was
    /// given), 64 lowercase hex digits: `sha256sum scene.toml` prints the same.
    pub scene_sha256: String,
    /// The backend and the settings it was run with.
    pub settings: BackendSettings,
    /// Logical cores the program could use (`std::thread::available_parallelism`; 1 when
    /// unknown).
    pub cores: usize,
}

/// The backend settings of a run (`provenance.settings`).
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct BackendSettings {
    /// The backend asked for, as the command line names it (`"auto"`, `"clarabel/dual"`, …).
    pub backend: String,
    /// The formulation it runs on: `"primal"` (sparse, in the displacements) or `"dual"`
    /// (condensed, in the contact forces); `auto` picks per attempt (see `attempts`).
    pub form: String,
    /// The relative KKT tolerance an answer must meet to count as solved.
    pub tolerance: f64,
    /// Wall-clock limit of the backend (with `auto`, of the whole chain), seconds; absent
    /// when there is none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_limit_s: Option<f64>,
    /// Iteration cap; absent when the backend chooses its own.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_iter: Option<usize>,
    /// `auto` only: the backends the chain may try, in order, when given by `--chain`
    /// (absent: auto's own rule, whose order `reason` explains).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub chain: Vec<String>,
}

/// One backend's run inside the `auto` chain (`result.json`'s `attempts`).
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct AttemptReport {
    /// Backend name.
    pub backend: String,
    /// Core-checked status, or `"error"` when the backend could not run.
    pub status: String,
    /// The backend's own verdict (absent after an error).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<crate::qp::QpStatus>")]
    pub backend_status: Option<String>,
    /// Its iterations.
    pub iterations: usize,
    /// Its wall-clock time, seconds.
    pub solve_s: f64,
    /// Its note, or the error.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub message: Option<String>,
}

/// One warning of `result.json`: its one-line message and the figures of its kind (`kind`,
/// `pair`, counts, places; see [`ModelWarning`]).
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct WarningReport {
    /// The warning in one line (as printed to stderr).
    pub message: String,
    /// Its kind and figures.
    #[serde(flatten)]
    pub warning: ModelWarning,
}

/// Per-body fields for output files.
#[derive(Debug, Clone)]
pub struct BodyFields {
    /// Nodal displacements.
    pub displacement: Vec<[f64; 2]>,
    /// Stresses (σₓₓ, σᵧᵧ, σₓᵧ, σ_zz) per cell.
    pub stress: Vec<[f64; 4]>,
    /// Von Mises stress per cell.
    pub von_mises: Vec<f64>,
    /// Contact pressure per node (0 away from contact).
    pub contact_pressure: Vec<f64>,
}

/// A row counts as active when its multiplier exceeds 10⁻⁶ of the force scale (the larger of the
/// largest multiplier and the total applied load), so round-off multipliers never count.
pub fn is_active(multiplier: f64, force_scale: f64) -> bool {
    multiplier > 1e-6 * force_scale && multiplier > 0.0
}

/// Displacement at `point` of a mesh by interpolation (`None` if the point is in no cell).
pub fn interpolate(mesh: &Mesh, u: &[[f64; 2]], point: Point, tol: f64) -> Option<[f64; 2]> {
    let combine = |nodes: &[usize], w: &[f64]| {
        let mut r = [0.0, 0.0];
        for (n, wi) in nodes.iter().zip(w) {
            r[0] += wi * u[*n][0];
            r[1] += wi * u[*n][1];
        }
        r
    };
    match &mesh.cells {
        Cells::Triangles(t) => t.iter().find_map(|c| {
            let [a, b, d] = c.map(|n| mesh.nodes[n]);
            let area = crate::geometry::orient(a, b, d);
            let w = [
                crate::geometry::orient(point, b, d) / area,
                crate::geometry::orient(a, point, d) / area,
                crate::geometry::orient(a, b, point) / area,
            ];
            let eps = tol / crate::geometry::distance(a, b).max(f64::MIN_POSITIVE);
            w.iter().all(|x| *x >= -eps).then(|| combine(c, &w))
        }),
        Cells::Quads(q) => q.iter().find_map(|c| {
            let p = c.map(|n| mesh.nodes[n]);
            let (xi, eta) = quad_local(p, point)?;
            let eps = 1e-9;
            if xi.abs() > 1.0 + eps || eta.abs() > 1.0 + eps {
                return None;
            }
            let w = [
                0.25 * (1.0 - xi) * (1.0 - eta),
                0.25 * (1.0 + xi) * (1.0 - eta),
                0.25 * (1.0 + xi) * (1.0 + eta),
                0.25 * (1.0 - xi) * (1.0 + eta),
            ];
            Some(combine(c, &w))
        }),
    }
}

/// Local coordinates (ξ, η) of a point in a bilinear quad, by Newton's method.
fn quad_local(p: [Point; 4], x: Point) -> Option<(f64, f64)> {
    let (mut xi, mut eta) = (0.0_f64, 0.0_f64);
    for _ in 0..30 {
        let n = [
            0.25 * (1.0 - xi) * (1.0 - eta),
            0.25 * (1.0 + xi) * (1.0 - eta),
            0.25 * (1.0 + xi) * (1.0 + eta),
            0.25 * (1.0 - xi) * (1.0 + eta),
        ];
        let dxi = [
            -0.25 * (1.0 - eta),
            0.25 * (1.0 - eta),
            0.25 * (1.0 + eta),
            -0.25 * (1.0 + eta),
        ];
        let deta = [
            -0.25 * (1.0 - xi),
            -0.25 * (1.0 + xi),
            0.25 * (1.0 + xi),
            0.25 * (1.0 - xi),
        ];
        let (mut fx, mut fy, mut j11, mut j12, mut j21, mut j22) =
            (-x[0], -x[1], 0.0, 0.0, 0.0, 0.0);
        for a in 0..4 {
            fx += n[a] * p[a][0];
            fy += n[a] * p[a][1];
            j11 += dxi[a] * p[a][0];
            j12 += deta[a] * p[a][0];
            j21 += dxi[a] * p[a][1];
            j22 += deta[a] * p[a][1];
        }
        let det = j11 * j22 - j12 * j21;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let dx = (j22 * fx - j12 * fy) / det;
        let dy = (-j21 * fx + j11 * fy) / det;
        xi -= dx;
        eta -= dy;
        if dx.abs() + dy.abs() < 1e-14 {
            break;
        }
    }
    (xi.is_finite() && eta.is_finite()).then_some((xi, eta))
}

/// Fields per body (displacement, stresses, contact pressure) for the output files.
pub fn body_fields(model: &Model, solution: &Solution) -> Vec<BodyFields> {
    let mut fields: Vec<BodyFields> = model
        .meshes
        .iter()
        .enumerate()
        .map(|(b, mesh)| {
            let displacement = model.body_displacements(b, &solution.displacement);
            let stress = fem::cell_stresses(mesh, &model.materials[b], &displacement);
            let von_mises = stress.iter().map(|s| element::von_mises(*s)).collect();
            BodyFields {
                displacement,
                stress,
                von_mises,
                contact_pressure: vec![0.0; mesh.nodes.len()],
            }
        })
        .collect();
    // Only active rows carry pressure into the fields: round-off multipliers (1e-17 from an
    // interior-point method) must not mark a node as in contact in the VTU or the SVG.
    let scale = active_scale(model, solution);
    let mut row = 0;
    for pair in &model.contacts {
        for r in &pair.rows {
            if let Some(&l) = solution.multipliers.get(row) {
                if is_active(l, scale) {
                    fields[pair.slave].contact_pressure[r.slave_node] += l / r.tributary;
                }
            }
            row += 1;
        }
    }
    fields
}

/// The force scale of [`is_active`] for a solution: the larger of the largest multiplier and the
/// total applied load Σ|fᵢ|.
pub fn active_scale(model: &Model, solution: &Solution) -> f64 {
    solution
        .multipliers
        .iter()
        .copied()
        .fold(0.0, f64::max)
        .max(model.load.iter().map(|f| f.abs()).sum())
}

/// Builds `result.json`'s content.
pub fn run_report(
    scene: &Scene,
    model: &Model,
    solution: &Solution,
    fields: &[BodyFields],
    tolerance: f64,
    timings: Timings,
) -> RunReport {
    let u = &solution.displacement;
    let balance = force_balance(scene, model, u, &solution.multipliers);
    let mut bodies = Vec::with_capacity(model.meshes.len());
    for (b, mesh) in model.meshes.iter().enumerate() {
        let figures = balance.bodies.get(b).copied().unwrap_or_default();
        let f = &fields[b];
        bodies.push(BodyReport {
            name: scene.bodies[b].name.clone(),
            nodes: mesh.nodes.len(),
            elements: mesh.cells.len(),
            max_displacement: f
                .displacement
                .iter()
                .map(|d| d[0].hypot(d[1]))
                .fold(0.0, f64::max),
            reaction: figures.reaction,
            applied: figures.applied,
            contact_force: figures.contact,
            max_von_mises: f.von_mises.iter().copied().fold(0.0, f64::max),
        });
    }
    let largest = active_scale(model, solution);
    let bu = mat_vec(&model.constraints, u);
    let mut contacts = Vec::with_capacity(model.contacts.len());
    let mut row = 0;
    let mut active_total = 0;
    for pair in &model.contacts {
        let mut nodes = Vec::with_capacity(pair.rows.len());
        let mut active = 0;
        let mut normal_force = 0.0;
        let slave_nodes: Vec<usize> = pair.rows.iter().map(|r| r.slave_node).collect();
        let arc = interface_arc(&model.meshes[pair.slave], &slave_nodes);
        for (r, place) in pair.rows.iter().zip(&arc) {
            let l = solution.multipliers.get(row).copied().unwrap_or(0.0);
            let on = is_active(l, largest);
            if on {
                active += 1;
            }
            normal_force += l;
            nodes.push(ContactNodeReport {
                x: r.position[0],
                y: r.position[1],
                gap: model.gap[row] - bu[row],
                initial_gap: r.gap,
                multiplier: l,
                pressure: l / r.tributary,
                active: on,
                weight: r.tributary,
                s: place.s,
                piece: place.piece,
            });
            row += 1;
        }
        active_total += active;
        let spec = &scene.contacts[pair.pair];
        contacts.push(ContactReport {
            bodies: spec.bodies.map(|k| scene.bodies[k].name.clone()),
            slave: scene.bodies[pair.slave].name.clone(),
            formulation: pair.formulation,
            conforming: pair.conforming,
            constraints: pair.rows.len(),
            active,
            normal_force,
            nodes,
        });
    }
    let tol = scene.tolerance();
    let probes = scene
        .probes
        .iter()
        .map(|p| ProbeReport {
            name: p.name.clone(),
            body: scene.bodies[p.body].name.clone(),
            point: p.point,
            displacement: interpolate(
                &model.meshes[p.body],
                &fields[p.body].displacement,
                p.point,
                tol,
            )
            .unwrap_or([f64::NAN, f64::NAN]),
        })
        .collect();
    RunReport {
        scene: scene.title.clone(),
        backend: solution.backend.clone(),
        status: solution.status.as_str().to_string(),
        tolerance,
        effects: model.effects.clone(),
        dofs: model.free.len(),
        constraints: model.rows(),
        active_constraints: active_total,
        iterations: solution.iterations,
        objective: solution.objective,
        residuals: solution.residuals,
        timing_s: timings,
        bodies,
        contacts,
        probes,
        force_balance: balance.relative,
        message: solution.message.clone(),
        backend_status: solution.backend_status.as_str().to_string(),
        warnings: model
            .warnings
            .iter()
            .map(|w| WarningReport {
                message: w.to_string(),
                warning: w.clone(),
            })
            .collect(),
        attempts: Vec::new(),
        chosen: None,
        reason: None,
        provenance: None,
    }
}
