//! Which boundary nodes or edges of a body's mesh a support or a load acts on: a physical group
//! of its Gmsh mesh, or a region box.

use crate::geometry::{self, Point};
use crate::mesh::gmsh::MeshGroup;
use crate::scene::Body;

/// A selection of boundary nodes and edges.
#[derive(Debug, Clone, Copy)]
pub enum Selection<'a> {
    /// The nodes and edges of a physical group (`None`: the body's mesh has no such group, so
    /// nothing is selected).
    Group(Option<&'a MeshGroup>),
    /// The nodes in a box `[x1, x2, y1, y2]` (within the tolerance), the edges with both ends
    /// in it.
    Box([f64; 4]),
}

impl<'a> Selection<'a> {
    /// The selection of a section naming `group` (of `body`'s mesh) or else `region`.
    pub fn of(group: Option<&str>, region: [f64; 4], body: &'a Body) -> Self {
        match group {
            Some(g) => Selection::Group(body.group(g)),
            None => Selection::Box(region),
        }
    }

    /// True when it holds boundary node `node` (at `p`).
    pub fn node(&self, node: usize, p: Point, tol: f64) -> bool {
        match self {
            Selection::Group(g) => g.is_some_and(|g| g.has_node(node)),
            Selection::Box(region) => geometry::in_box(p, region, tol),
        }
    }

    /// True when it holds the boundary edge `[a, b]` (at `pa`, `pb`).
    pub fn edge(&self, [a, b]: [usize; 2], [pa, pb]: [Point; 2], tol: f64) -> bool {
        match self {
            Selection::Group(g) => g.is_some_and(|g| g.has_edge(a, b)),
            Selection::Box(region) => {
                geometry::in_box(pa, region, tol) && geometry::in_box(pb, region, tol)
            }
        }
    }
}
