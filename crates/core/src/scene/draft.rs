//! The scene as validation leaves it, before import: every value of the TOML checked and every
//! name resolved, with each Gmsh body still a file name and each physical group still a name.
//! The import stage (`import.rs`) reads the files and turns a [`Draft`] into a
//! [`Scene`](super::Scene).

use super::file::Plane;
use super::types::{ContactPair, LoadStep, Probe, Reference, Traction};
use crate::geometry::Point;
use crate::mesh::{ElementKind, Refinement};

/// A validated scene whose Gmsh files are not read yet.
#[derive(Debug)]
pub(super) struct Draft {
    /// Title (the file's, or "untitled").
    pub title: String,
    /// Plane strain or plane stress.
    pub plane: Plane,
    /// Thickness (1 for plane strain).
    pub thickness: f64,
    /// Body force per unit mass, if any.
    pub gravity: Option<[f64; 2]>,
    /// Bodies, in the file's order.
    pub bodies: Vec<DraftBody>,
    /// Prescribed displacements.
    pub dirichlet: Vec<DraftDirichlet>,
    /// Tractions.
    pub neumann: Vec<DraftNeumann>,
    /// Contact pairs.
    pub contacts: Vec<ContactPair>,
    /// Probes.
    pub probes: Vec<Probe>,
    /// The analytic answer, if the scene states one.
    pub reference: Option<Reference>,
    /// The named supports and loads (`[[dirichlet]]` names in order, then `[[neumann]]`'s).
    pub load_names: Vec<String>,
    /// The load path (empty: one step, full load).
    pub steps: Vec<LoadStep>,
}

impl Draft {
    /// True when the TOML gives every body's outline (no body is a Gmsh file): validation then
    /// checks where regions, probes and supports lie; otherwise the import does, once the files
    /// give the outlines (the scene's tolerance depends on all of them).
    pub fn outlines_known(&self) -> bool {
        self.bodies.iter().all(|b| b.polygon().is_some())
    }
}

/// A validated body.
#[derive(Debug)]
pub(super) struct DraftBody {
    /// Unique name.
    pub name: String,
    /// Young's modulus E.
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Mass density (only with gravity).
    pub density: Option<f64>,
    /// A polygon meshed by the program, or a Gmsh file.
    pub shape: Shape,
}

impl DraftBody {
    /// The polygon of a polygon body (None for a Gmsh body).
    pub fn polygon(&self) -> Option<&[Point]> {
        match &self.shape {
            Shape::Polygon(p) => Some(&p.polygon),
            Shape::Gmsh(_) => None,
        }
    }
}

/// Where a body's geometry comes from.
#[derive(Debug)]
pub(super) enum Shape {
    /// A polygon meshed by the program.
    Polygon(PolygonBody),
    /// A Gmsh file (`mesh = "…"`), relative to the scene file.
    Gmsh(String),
}

/// The geometry of a polygon body, checked.
#[derive(Debug)]
pub(super) struct PolygonBody {
    /// Vertices, counter-clockwise.
    pub polygon: Vec<Point>,
    /// Largest element edge.
    pub hmax: f64,
    /// Element type.
    pub element: ElementKind,
    /// Regions meshed finer than `hmax`.
    pub refine: Vec<Refinement>,
}

/// What a support or a traction acts on.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Place {
    /// The boundary inside a box `[x1, x2, y1, y2]`.
    Region([f64; 4]),
    /// A physical group of the body's Gmsh mesh.
    Group(String),
}

/// A validated `[[dirichlet]]` section.
#[derive(Debug)]
pub(super) struct DraftDirichlet {
    /// Name, for the load path.
    pub name: Option<String>,
    /// Body index.
    pub body: usize,
    /// Its box or group.
    pub place: Place,
    /// Prescribed `[ux, uy]`.
    pub value: [f64; 2],
    /// Which components are prescribed (`[x, y]`).
    pub components: [bool; 2],
}

/// A validated `[[neumann]]` section.
#[derive(Debug)]
pub(super) struct DraftNeumann {
    /// Name, for the load path.
    pub name: Option<String>,
    /// Body index.
    pub body: usize,
    /// Its box or group.
    pub place: Place,
    /// The traction field.
    pub traction: Traction,
}
