//! Initial overlap of the two bodies of a pair: which boundary nodes start inside the other
//! body, how deep, and the deepest overlap accepted as contact (see the parent module).

use super::search::SegmentIndex;
use super::{boundary_node_mask, Search};
use crate::geometry::{self, Point};
use crate::mesh::Mesh;

/// Where two bodies of a pair overlap before any load (see the [parent module](super)).
#[derive(Debug, Clone, PartialEq)]
pub struct Overlap {
    /// Slave nodes that start inside the master and got a row with a negative gap.
    pub slave_nodes: usize,
    /// Master boundary nodes that start inside the slave (node-to-segment rows constrain only
    /// slave nodes; these come out only as far as the slave nodes push the master).
    pub master_nodes: usize,
    /// Position of the deepest node found inside the other body.
    pub deepest: Point,
    /// Its depth: distance to the other body's boundary.
    pub depth: f64,
    /// Index of the body the deepest node belongs to.
    pub deepest_body: usize,
}

/// For every node of `mesh`: `Some(depth)` when it is a boundary node lying in the closed body
/// `other` (polygon `polygon`, within `tol`), with `depth` its distance to `other`'s boundary
/// (≤ `tol` on it); `None` when it is outside or not a boundary node.
///
/// The depth is the minimum over `other`'s boundary edges of the distance from
/// [`geometry::project_on_segment`].  [`Search::Indexed`] takes that minimum over the edges an
/// R-tree finds within the distance of the nearest one (plus a rounding margin), which holds
/// every edge that attains it: the same value as the scan over every edge, in O(log n) per node
/// instead of O(n).
pub(super) fn depths_inside(
    mesh: &Mesh,
    other: &Mesh,
    polygon: &[Point],
    tol: f64,
    search: Search,
) -> Vec<Option<f64>> {
    let on = boundary_node_mask(mesh);
    let bbox = geometry::bounding_box(polygon);
    let inside: Vec<bool> = mesh
        .nodes
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            on[i] && geometry::in_box(p, &bbox, tol) && geometry::contains(polygon, p, tol)
        })
        .collect();
    let distance = |p: Point, e: usize| {
        let [a, b] = other.boundary[e];
        geometry::project_on_segment(p, other.nodes[a], other.nodes[b]).1
    };
    let index = match search {
        Search::Indexed if inside.iter().any(|x| *x) => {
            Some(SegmentIndex::new(&other.nodes, &other.boundary))
        }
        _ => None,
    };
    mesh.nodes
        .iter()
        .zip(&inside)
        .map(|(&p, &inside)| {
            if !inside {
                return None;
            }
            let depth = match &index {
                Some(index) => match index.nearest(p).next() {
                    Some((e, _)) => index
                        .within(p, distance(p, e))
                        .map(|e| distance(p, e))
                        .fold(f64::INFINITY, f64::min),
                    None => f64::INFINITY,
                },
                None => (0..other.boundary.len())
                    .map(|e| distance(p, e))
                    .fold(f64::INFINITY, f64::min),
            };
            Some(depth)
        })
        .collect()
}

/// True when a depth from [`depths_inside`] is strictly inside (deeper than `tol`).
pub(super) fn strictly_inside(depth: Option<f64>, tol: f64) -> bool {
    depth.is_some_and(|d| d > tol)
}

/// The deepest strictly inside entry of a depth list: (node, depth).
pub(super) fn deepest(depths: &[Option<f64>], tol: f64) -> Option<(usize, f64)> {
    depths
        .iter()
        .enumerate()
        .filter_map(|(i, d)| d.filter(|d| *d > tol).map(|d| (i, d)))
        .fold(None, |best, (i, d)| match best {
            Some((_, bd)) if bd >= d => best,
            _ => Some((i, d)),
        })
}
