//! The TOML scene file as written by the user (`docs/scene.md`), before validation.
//!
//! Every table refuses unknown keys, so a typo is an error and never silently ignored.  Arrays are
//! read as vectors of any length, so that validation can refuse a wrong length naming the section
//! and the key (a fixed-size array would let serde drop surplus numbers silently).

use serde::Deserialize;

use crate::mesh::ElementKind;

/// Plane-strain or plane-stress idealisation.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, serde::Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum Plane {
    /// Plane strain (ε_zz = 0), the seed's choice; per unit thickness.
    #[default]
    Strain,
    /// Plane stress (σ_zz = 0), with an optional thickness.
    Stress,
}

/// How a contact pair's constraint rows are built (`docs/scene.md`, "Contact formulations").
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, serde::Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Formulation {
    /// One row per slave node on the closest master segment (the seed's method, single pass).
    #[default]
    NodeToSegment,
    /// Segment-to-segment mortar rows with a dual (biorthogonal) slave basis: one row per slave
    /// node, weighted gaps, passes the contact patch test on non-matching meshes.
    Mortar,
}

/// A displacement component.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Component {
    /// Horizontal.
    X,
    /// Vertical.
    Y,
}

/// The whole file.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Free-text title.
    pub title: Option<String>,
    /// Modelling choices.
    pub model: Option<ModelSection>,
    /// `[[body]]` tables.
    #[serde(default)]
    pub body: Vec<BodySection>,
    /// `[[dirichlet]]` tables.
    #[serde(default)]
    pub dirichlet: Vec<DirichletSection>,
    /// `[[neumann]]` tables.
    #[serde(default)]
    pub neumann: Vec<NeumannSection>,
    /// `[[contact]]` tables.
    #[serde(default)]
    pub contact: Vec<ContactSection>,
    /// `[[probe]]` tables.
    #[serde(default)]
    pub probe: Vec<ProbeSection>,
    /// `[reference]`: the scene's analytic answer, for accuracy studies.
    pub reference: Option<ReferenceSection>,
    /// `[[step]]` tables: the quasi-static load path (none: one step, full load).
    #[serde(default)]
    pub step: Vec<StepSection>,
}

/// `[[step]]`: the factors of the named loads at the step's end, reached in `increments` equal
/// increments from the previous step's.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StepSection {
    /// Factor per named `[[neumann]]` or `[[dirichlet]]` (`name`); a named load not listed has
    /// factor 0 in this step; unnamed loads have factor 1 throughout.
    #[serde(default)]
    pub loads: std::collections::BTreeMap<String, f64>,
    /// Number of equal increments (≥ 1, default 1).
    pub increments: Option<i64>,
}

/// `[model]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelSection {
    /// `"strain"` (default) or `"stress"`.
    #[serde(default)]
    pub plane: Plane,
    /// Thickness, plane stress only.
    pub thickness: Option<f64>,
    /// Body force per unit mass `[gx, gy]`; every body then needs `density`.
    pub gravity: Option<Vec<f64>>,
}

/// `[[body]]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BodySection {
    /// Unique name.
    pub name: String,
    /// Vertices of a simple polygon, either orientation (not with `mesh`).
    pub polygon: Option<Vec<Vec<f64>>>,
    /// Largest element edge (with `polygon`; not with `mesh`).
    pub hmax: Option<f64>,
    /// A Gmsh MSH 4.1 file (ASCII or binary), relative to the scene file, instead of `polygon`.
    pub mesh: Option<String>,
    /// `"p1"` (default) or `"q1"`; not with `mesh` (the file's elements decide).
    pub element: Option<ElementKind>,
    /// Young's modulus E.
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Mass density (only with `[model] gravity`).
    pub density: Option<f64>,
    /// `[[body.refine]]` tables: finer meshes near regions.
    #[serde(default)]
    pub refine: Vec<RefineSection>,
}

/// `[[body.refine]]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RefineSection {
    /// Box `[x1, x2, y1, y2]` meshed with the finer size.
    pub region: Vec<f64>,
    /// Largest element edge inside the box.
    pub hmax: f64,
}

/// `[[dirichlet]]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DirichletSection {
    /// Optional name, for `[[step]] loads` (unique among supports and loads).
    pub name: Option<String>,
    /// Body name.
    pub body: String,
    /// Box `[x1, x2, y1, y2]` (or `group`).
    pub region: Option<Vec<f64>>,
    /// Physical group of the body's Gmsh mesh (or `region`).
    pub group: Option<String>,
    /// Prescribed displacement, default `[0, 0]`.
    pub value: Option<Vec<f64>>,
    /// Constrained components, default both.
    pub components: Option<Vec<Component>>,
}

/// `[[neumann]]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NeumannSection {
    /// Optional name, for `[[step]] loads` (unique among supports and loads).
    pub name: Option<String>,
    /// Body name.
    pub body: String,
    /// Box `[x1, x2, y1, y2]` (or `group`).
    pub region: Option<Vec<f64>>,
    /// Physical group of the body's Gmsh mesh (or `region`).
    pub group: Option<String>,
    /// Constant traction `[tx, ty]`.
    pub traction: Option<Vec<f64>>,
    /// Three non-collinear points of a linear traction field.
    pub points: Option<Vec<Vec<f64>>>,
    /// tx at the three points.
    pub tx: Option<Vec<f64>>,
    /// ty at the three points.
    pub ty: Option<Vec<f64>>,
}

/// `[[contact]]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContactSection {
    /// The two body names.
    pub bodies: Vec<String>,
    /// Optional box limiting the candidate boundary nodes (master edges that cross it count too).
    pub region: Option<Vec<f64>>,
    /// Optional physical group limiting the candidate nodes of each body of the pair whose Gmsh
    /// mesh defines it (at least one must).
    pub group: Option<String>,
    /// Optional slave side.
    pub slave: Option<String>,
    /// `"node-to-segment"` (default) or `"mortar"`.
    #[serde(default)]
    pub formulation: Formulation,
    /// Coulomb friction coefficient μ ≥ 0 (absent or 0: frictionless); not with `tresca`.
    pub friction: Option<f64>,
    /// Tresca slip bound ≥ 0, a traction (force per unit length and unit thickness; absent or
    /// 0: frictionless); not with `friction`.
    pub tresca: Option<f64>,
}

/// `[[probe]]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProbeSection {
    /// Name in the report.
    pub name: String,
    /// Body name.
    pub body: String,
    /// Point of the undeformed body.
    pub point: Vec<f64>,
}

/// `[reference]`: analytic values the computed contact pressure is compared with.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ReferenceSection {
    /// 1-based contact pair the values are about (default 1).
    pub pair: Option<usize>,
    /// Centre `[x, y]` of the contact zone (Hertz: the point of first contact).
    pub centre: Option<Vec<f64>>,
    /// Half-width a of the contact zone (Hertz).
    pub half_width: Option<f64>,
    /// Peak pressure p₀ (Hertz).
    pub peak_pressure: Option<f64>,
    /// Uniform pressure p (contact patch test).
    pub pressure: Option<f64>,
    /// Relative radius of curvature R (Cattaneo–Mindlin, with `contact_modulus` and `friction`).
    pub radius: Option<f64>,
    /// Contact modulus E* (Cattaneo–Mindlin).
    pub contact_modulus: Option<f64>,
    /// Coulomb's μ of the pair (Cattaneo–Mindlin).
    pub friction: Option<f64>,
}
