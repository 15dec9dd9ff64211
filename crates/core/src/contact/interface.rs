//! What the contact search takes: each pair as an [`Interface`] of two [`Side`]s — typed values
//! built from the scene by the contact effect (`crate::effects::contact`), so that contact
//! numerics never read the scene file's structures.

use crate::geometry::Point;
use crate::mesh::gmsh::MeshGroup;
use crate::scene::{Formulation, Friction};

/// One body of a contact pair, as the search sees it.
#[derive(Debug, Clone, Copy)]
pub struct Side<'a> {
    /// Body index (its mesh in the slice given to [`super::contact_rows`]).
    pub body: usize,
    /// Body name (for messages).
    pub name: &'a str,
    /// The body's outline, counter-clockwise (the closed region the other side must stay out of).
    pub outline: &'a [Point],
    /// The body's largest element edge.
    pub hmax: f64,
    /// The body's surface compliance 1/E′ — (1 − ν²)/E in plane strain, 1/E in plane stress
    /// (`Material::surface_compliance`): how far its surface gives under a pressure, relative to the other side's (frictional mortar rows act along the interface
    /// the two compliances put between the bodies' surfaces; see `mortar::Frame`).
    pub compliance: f64,
    /// When the pair names a physical group and this body's Gmsh mesh defines it: only its
    /// nodes are candidates.
    pub group: Option<&'a MeshGroup>,
}

/// One contact pair.
#[derive(Debug, Clone, Copy)]
pub struct Interface<'a> {
    /// The two bodies, in the scene's order.
    pub sides: [Side<'a>; 2],
    /// Box limiting candidate nodes.
    pub region: Option<[f64; 4]>,
    /// The slave body's index, when the scene names it.
    pub slave: Option<usize>,
    /// How the pair's rows are built.
    pub formulation: Formulation,
    /// The pair's friction law (`None`: frictionless); carried to its rows, not used by the
    /// search.
    pub friction: Option<Friction>,
}

impl Interface<'_> {
    /// The deepest initial overlap accepted as contact: the larger `hmax` of the two bodies.
    /// Deeper overlaps are refused ([`super::ContactError::DeepOverlap`]).
    pub fn overlap_limit(&self) -> f64 {
        self.sides[0].hmax.max(self.sides[1].hmax)
    }

    /// The side of body `b` (the first side when `b` is in neither).
    pub fn side(&self, b: usize) -> &Side<'_> {
        if self.sides[1].body == b {
            &self.sides[1]
        } else {
            &self.sides[0]
        }
    }

    /// Whether body `b` is one of the two sides.
    pub fn touches(&self, b: usize) -> bool {
        self.sides.iter().any(|s| s.body == b)
    }
}
