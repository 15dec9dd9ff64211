//! Scenes: the TOML contract of `docs/scene.md`, parsed with unknown keys refused, validated into
//! typed values whose errors name the section, the body and the key at fault (`validate/`, which
//! reads no file), then imported (`import/`: the Gmsh files read, their physical groups
//! resolved).
//!
//! ```
//! use signorini_core::scene::Scene;
//! let scene = Scene::from_toml(r#"
//!     [[body]]
//!     name = "block"
//!     polygon = [[0, 0], [1, 0], [1, 1], [0, 1]]
//!     hmax = 0.5
//!     young = 1.0
//!     poisson = 0.3
//!     [[dirichlet]]
//!     body = "block"
//!     region = [0, 1, 0, 0]
//! "#).unwrap();
//! assert_eq!(scene.bodies[0].name, "block");
//! let err = Scene::from_toml("[[body]]\nname = 'b'\nyoung = 1.0\npoisson = 0.3").unwrap_err();
//! assert!(err.to_string().contains("polygon"));
//! ```

mod draft;
mod error;
mod file;
mod import;
mod types;
mod validate;

use std::path::Path;

pub use error::SceneError;
pub use file::{
    BodySection, Component, ContactSection, DirichletSection, ModelSection, NeumannSection, Plane,
    ProbeSection, ReferenceSection, RefineSection, SceneFile,
};
pub use types::{
    Body, Cattaneo, ContactPair, Dirichlet, Formulation, Friction, LoadStep, Neumann, Probe,
    Reference, Traction,
};
pub use validate::{name_forbidden, MAX_COEFFICIENT, MIN_COEFFICIENT};

use crate::geometry;

pub use crate::geometry::REGION_TOLERANCE;

/// A validated scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Title (the file's, or "untitled").
    pub title: String,
    /// Plane strain or plane stress.
    pub plane: Plane,
    /// Thickness (1 for plane strain).
    pub thickness: f64,
    /// Body force per unit mass, if any.
    pub gravity: Option<[f64; 2]>,
    /// Bodies.
    pub bodies: Vec<Body>,
    /// Prescribed displacements.
    pub dirichlet: Vec<Dirichlet>,
    /// Tractions.
    pub neumann: Vec<Neumann>,
    /// Contact pairs.
    pub contacts: Vec<ContactPair>,
    /// Probes.
    pub probes: Vec<Probe>,
    /// The analytic answer, if the scene states one.
    pub reference: Option<Reference>,
    /// The named supports and loads (`[[dirichlet]]` names in order, then `[[neumann]]`'s).
    pub load_names: Vec<String>,
    /// The load path (`[[step]]`; empty: one step, full load).
    pub steps: Vec<LoadStep>,
}

impl Scene {
    /// Reads and validates a scene file.
    pub fn from_path(path: &Path) -> Result<Self, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
            path: path.display().to_string(),
            source,
        })?;
        let base = path.parent().unwrap_or(Path::new(""));
        Self::from_toml_in(&text, base)
    }

    /// Parses and validates a scene from TOML text.  A body with `mesh` (a Gmsh file, relative
    /// to the scene file) is refused here, since text has no directory: use [`Scene::from_path`]
    /// or [`Scene::from_toml_in`].
    pub fn from_toml(text: &str) -> Result<Self, SceneError> {
        let file: SceneFile =
            toml::from_str(text).map_err(|e| SceneError::Syntax(e.to_string()))?;
        import::import(validate::validate(file)?, None)
    }

    /// Parses and validates a scene from TOML text whose `mesh` paths are relative to `base`
    /// (the directory of the scene file).
    pub fn from_toml_in(text: &str, base: &Path) -> Result<Self, SceneError> {
        let file: SceneFile =
            toml::from_str(text).map_err(|e| SceneError::Syntax(e.to_string()))?;
        import::import(validate::validate(file)?, Some(base))
    }

    /// Diagonal of the bounding box of all bodies: the scene's length scale.
    pub fn size(&self) -> f64 {
        let b = geometry::bounding_box(self.bodies.iter().flat_map(|b| b.polygon.iter()));
        (b[1] - b[0]).hypot(b[3] - b[2])
    }

    /// Absolute tolerance for matching regions and points: [`REGION_TOLERANCE`] × size.
    pub fn tolerance(&self) -> f64 {
        REGION_TOLERANCE * self.size()
    }

    /// The factor a load or support named `name` (`None`: unnamed) has at the end of the load
    /// path: 1 for an unnamed one or without `[[step]]`, else the last step's factor for it
    /// (docs/scene.md, "Load steps").  What the written results — the last increment's — carry.
    pub fn final_factor(&self, name: Option<&str>) -> f64 {
        let (Some(name), Some(last)) = (name, self.steps.last()) else {
            return 1.0;
        };
        self.load_names
            .iter()
            .position(|n| n == name)
            .and_then(|k| last.factors.get(k))
            .copied()
            .unwrap_or(1.0)
    }

    /// Index of the body with this name.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }
}
