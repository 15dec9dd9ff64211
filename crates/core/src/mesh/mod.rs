//! Meshes of the bodies: P1 triangles (constrained Delaunay with refinement, every edge ≤ hmax,
//! minimum angle bound) and structured Q1 quadrilaterals for axis-aligned rectangles.
//!
//! Boundary discretisation is deterministic so that two touching bodies with equal `hmax` get
//! coincident interface nodes (conforming), and every requested break point on the boundary
//! (other bodies' corners, region-box crossings) becomes a mesh vertex.

use serde::{Deserialize, Serialize};

use crate::geometry::Point;

/// Element type of a body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ElementKind {
    /// Linear triangles.
    #[default]
    P1,
    /// Bilinear quadrilaterals on a structured grid (axis-aligned rectangles only).
    Q1,
}

/// Cells of a mesh, counter-clockwise node indices.
#[derive(Debug, Clone, PartialEq)]
pub enum Cells {
    /// Linear triangles.
    Triangles(Vec<[usize; 3]>),
    /// Bilinear quadrilaterals.
    Quads(Vec<[usize; 4]>),
}

impl Cells {
    /// Number of cells.
    pub fn len(&self) -> usize {
        match self {
            Cells::Triangles(t) => t.len(),
            Cells::Quads(q) => q.len(),
        }
    }

    /// True when there are no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Node indices of cell `i` (3 or 4 of them).
    pub fn cell(&self, i: usize) -> &[usize] {
        match self {
            Cells::Triangles(t) => &t[i],
            Cells::Quads(q) => &q[i],
        }
    }
}

/// One body's mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Node coordinates.
    pub nodes: Vec<Point>,
    /// Elements, counter-clockwise.
    pub cells: Cells,
    /// Boundary edges `[a, b]`, oriented so that the body lies on the left (counter-clockwise).
    pub boundary: Vec<[usize; 2]>,
}
