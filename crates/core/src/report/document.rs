//! The types `result.json` is written from: [`RunReport`] and its parts (see `docs/scene.md`).

use schemars::JsonSchema;
use serde::Serialize;

use super::friction::ContactState;
use crate::geometry::Point;
use crate::model::{Effect, ModelWarning};
use crate::qp::CoulombMethod;
use crate::qp::KktResiduals;
use crate::scene::{Formulation, Friction};
use crate::solve::{CoulombRun, StepRecord};

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
    /// unconstrained stiffness (see [`balance`](super::balance)).
    pub reaction: [f64; 2],
    /// The applied loads `[Fx, Fy]`, integrated analytically from the scene's tractions and
    /// gravity (see [`balance`](super::balance)).
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
    /// Whether the row counts as in contact ([`is_active`](super::is_active)); the VTU's pressure, the SVG's
    /// contact edges and `pressure.svg`'s filled markers use the same test.
    pub active: bool,
    /// The length the multiplier is divided by to give `pressure` (the row's
    /// [`tributary`](crate::contact::ContactRow::tributary)): node-to-segment, the node's
    /// tributary length on the slave interface (half of each adjacent slave edge facing the
    /// master); mortar, D_jj = ∫N_j over the part of the slave interface the master covers.
    pub weight: f64,
    /// Arc-length coordinate of the node along the pair's slave interface, in the scene's length
    /// unit (see [`arc`](super::arc) for its origin, direction and how disjoint pieces are laid end to end).
    pub s: f64,
    /// The interface piece the node lies on (0-based, in the order of [`arc`](super::arc); one piece for a
    /// connected interface).
    pub piece: usize,
    /// Frictional pairs only: the tangential force λₜ on the slave node along the row's tangent
    /// t = (n_y, −n_x) (per unit thickness; |λₜ| ≤ the friction bound).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangential_multiplier: Option<f64>,
    /// Frictional pairs only: λₜ / `weight`, the tangential traction along t.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangential_traction: Option<f64>,
    /// Frictional pairs only: the slave node's slip relative to the master along t.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slip: Option<f64>,
    /// Frictional pairs only: `open` (not active), `stick` or `slip` (see
    /// [`SLIP_FRACTION`](super::friction::SLIP_FRACTION)).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub state: Option<ContactState>,
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
    /// Rows with a positive multiplier (see [`is_active`](super::is_active)).
    pub active: usize,
    /// Sum of the multipliers: the total normal force transmitted, as a sum of magnitudes
    /// along each row's own normal (it exceeds |`force`| where those normals differ).
    pub normal_force: f64,
    /// The resultant vector of the pair's contact forces on the slave body, Σ λ n + λₜ t over
    /// its rows (normal and tangential): what the master exerts on the slave through this pair.
    /// It equals the slave's `contact_force` when the slave is in no other pair, and so balances
    /// its loads and reactions.
    pub force: [f64; 2],
    /// Frictional pairs only: the friction law, `{"coulomb": μ}` or `{"tresca": bound}`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction: Option<Friction>,
    /// Frictional pairs only: the sum of the tangential multipliers (along each row's tangent).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangential_force: Option<f64>,
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
    /// ½uᵀAu − fᵀu on the free DOFs (with friction plus Σ sᵢ |rᵢ| over the tangential rows).
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
    /// components, divided by the largest of those three figures (see [`balance`](super::balance) for why this is
    /// a real check: it is the summed equilibrium residual of the free DOFs, not zero by
    /// construction).
    pub force_balance: f64,
    /// The backend's note, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub message: Option<String>,
    /// The backend's own verdict before the core's residual check (`status` is the program's).
    #[schemars(with = "crate::qp::QpStatus")]
    pub backend_status: String,
    /// With `[[step]]` only: every increment of the load path, in order (the fields above are
    /// the last's).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub steps: Vec<StepRecord>,
    /// Coulomb friction only: what the fixed point over Tresca problems did (of the last
    /// increment).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coulomb: Option<CoulombRun>,
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
    /// Coulomb friction's method when one was asked for (`fixed-point`, `newton`); absent for
    /// the default `auto` (see [`crate::qp::CoulombMethod`]).
    #[serde(skip_serializing_if = "is_auto")]
    pub coulomb: CoulombMethod,
}

/// Whether the Coulomb method is the default (not written).
fn is_auto(method: &CoulombMethod) -> bool {
    *method == CoulombMethod::Auto
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
