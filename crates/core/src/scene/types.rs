//! The validated values of a scene: bodies, supports, loads, contact pairs and probes.

use std::sync::Arc;

use crate::geometry::Point;
use crate::mesh::gmsh::{ImportedMesh, MeshGroup};
use crate::mesh::{ElementKind, Refinement};

pub use super::file::Formulation;

/// One elastic body.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Unique name.
    pub name: String,
    /// Vertices, counter-clockwise (reordered if given clockwise); for a Gmsh body its boundary
    /// loop (every boundary node).
    pub polygon: Vec<Point>,
    /// Largest element edge (for a Gmsh body: its longest element edge).
    pub hmax: f64,
    /// Element type.
    pub element: ElementKind,
    /// Young's modulus E.
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Mass density (only used with gravity).
    pub density: Option<f64>,
    /// Regions meshed finer than `hmax` (`[[body.refine]]`).
    pub refine: Vec<Refinement>,
    /// The mesh read from the body's Gmsh file (`mesh = "…"`), used instead of meshing `polygon`.
    pub imported: Option<Arc<ImportedMesh>>,
}

impl Body {
    /// The physical group `name` of the body's Gmsh mesh (None for polygon bodies).
    pub fn group(&self, name: &str) -> Option<&MeshGroup> {
        self.imported.as_ref().and_then(|m| m.group(name))
    }
}

/// A prescribed displacement on the boundary nodes in a box.
#[derive(Debug, Clone, PartialEq)]
pub struct Dirichlet {
    /// Name, for the load path (`[[step]]`).
    pub name: Option<String>,
    /// Body index.
    pub body: usize,
    /// Box `[x1, x2, y1, y2]`; with `group`, the bounding box of the group's nodes.
    pub region: [f64; 4],
    /// Physical group of the body's Gmsh mesh that selects the nodes instead of the box.
    pub group: Option<String>,
    /// Prescribed `[ux, uy]`.
    pub value: [f64; 2],
    /// Which components are prescribed (`[x, y]`).
    pub components: [bool; 2],
}

/// A surface traction field t(x, y) = (a·x + b·y + c) per component.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Traction {
    /// `[[a, b, c] for tx, [a, b, c] for ty]`.
    pub coefficients: [[f64; 3]; 2],
}

impl Traction {
    /// A constant traction.
    pub fn constant(t: [f64; 2]) -> Self {
        Self {
            coefficients: [[0.0, 0.0, t[0]], [0.0, 0.0, t[1]]],
        }
    }

    /// The traction at a point.
    pub fn at(&self, p: Point) -> [f64; 2] {
        let f = |c: &[f64; 3]| c[0] * p[0] + c[1] * p[1] + c[2];
        [f(&self.coefficients[0]), f(&self.coefficients[1])]
    }
}

/// A traction on the boundary edges in a box.
#[derive(Debug, Clone, PartialEq)]
pub struct Neumann {
    /// Name, for the load path (`[[step]]`).
    pub name: Option<String>,
    /// Body index.
    pub body: usize,
    /// Box `[x1, x2, y1, y2]`; with `group`, the bounding box of the group's nodes.
    pub region: [f64; 4],
    /// Physical group of the body's Gmsh mesh that selects the edges instead of the box.
    pub group: Option<String>,
    /// The traction field (force per unit length and unit thickness).
    pub traction: Traction,
}

/// One `[[step]]` of the load path.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadStep {
    /// Factor of each named load at the step's end, in the order of
    /// [`crate::scene::Scene::load_names`] (0 for a name the step does not list).
    pub factors: Vec<f64>,
    /// Equal increments from the previous step's factors (≥ 1).
    pub increments: usize,
}

/// A pair of bodies that may touch.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactPair {
    /// The two body indices.
    pub bodies: [usize; 2],
    /// Optional box limiting candidate nodes.
    pub region: Option<[f64; 4]>,
    /// Optional physical group limiting the candidate nodes of each body of the pair whose
    /// Gmsh mesh defines it.
    pub group: Option<String>,
    /// Slave body, when the scene names it.
    pub slave: Option<usize>,
    /// How the pair's rows are built.
    pub formulation: Formulation,
    /// The friction law, `None` for a frictionless pair (no tangential rows at all).
    pub friction: Option<Friction>,
}

/// The friction law of a contact pair (`[[contact]] friction` or `tresca`; docs/scene.md,
/// "Friction"); result.json writes it as `{"coulomb": μ}` or `{"tresca": s}`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Friction {
    /// Coulomb: |λₜ| ≤ μ λₙ at each row, μ > 0 (`friction = μ`).
    Coulomb(f64),
    /// Tresca: |λₜ| ≤ s·ℓ at each row, s > 0 a traction (force per unit length and unit
    /// thickness) and ℓ the row's tributary length (`tresca = s`).
    Tresca(f64),
}

impl Friction {
    /// The bound s of a node's tangential multiplier, given its normal multiplier `normal` and
    /// the length `length` that turns a traction into a force (a row's tributary length): μ
    /// max(0, normal) or Tresca's traction × length.  With a pressure and length 1, the bound
    /// of the tangential traction.
    pub fn bound(self, normal: f64, length: f64) -> f64 {
        match self {
            Friction::Coulomb(mu) => mu * normal.max(0.0),
            Friction::Tresca(traction) => traction * length,
        }
    }
}

/// A point whose displacement is reported.
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    /// Name.
    pub name: String,
    /// Body index.
    pub body: usize,
    /// Point of the undeformed body.
    pub point: Point,
}

/// The scene's analytic answer (`[reference]`), for accuracy studies: the values come from
/// formulas (Johnson's Hertz line contact, the patch test's uniform pressure, Cattaneo–Mindlin
/// partial slip), never from a finer solve.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    /// Contact pair index (0-based).
    pub pair: usize,
    /// Centre of the contact zone.
    pub centre: Option<Point>,
    /// Hertz half-width a.
    pub half_width: Option<f64>,
    /// Hertz peak pressure p₀.
    pub peak_pressure: Option<f64>,
    /// Uniform pressure p.
    pub pressure: Option<f64>,
    /// Cattaneo–Mindlin partial slip of a frictional Hertz contact (excludes the three values
    /// above: its a, p₀ and c follow from the run's own normal and tangential force).
    pub cattaneo: Option<Cattaneo>,
}

/// Cattaneo–Mindlin partial slip (Johnson 1985, §7.1, in 2-D): a cylinder of radius R pressed
/// by P and then sheared by Q < μP per unit length, with a = √(4PR/(πE*)), p₀ = 2P/(πa), the
/// stick zone |x| < c = a √(1 − Q/(μP)) and the tangential traction
/// q(x) = μ p₀/a (√(a² − x²) − √(c² − x²)) for |x| < c, μ p(x) for c < |x| < a.  P and Q are
/// the run's forces on the pair: a shift prescribed as a displacement transmits a force that
/// depends on the bodies' compliance, which the 2-D theory leaves undetermined.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cattaneo {
    /// Relative radius of curvature R of the two surfaces (1/R = 1/R₁ + 1/R₂).
    pub radius: f64,
    /// Contact modulus E*, 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂ (plane strain).
    pub contact_modulus: f64,
    /// Coulomb's μ (the pair's).
    pub friction: f64,
}
