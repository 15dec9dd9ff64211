//! Spatial index of boundary segments for the contact search: an R-tree (rstar) over the
//! segments' bounding boxes.
//!
//! Every query here is used the same way: the index only *narrows* the set of segments a
//! brute-force scan would look at, and the caller then evaluates the narrowed set with exactly
//! the arithmetic of the scan, in the scan's order.  The index never computes a distance that
//! reaches a result.  So the results are bit-identical to the scan as long as the narrowed set
//! holds every segment that could change the result — which the queries guarantee with a
//! rounding margin ([`SegmentIndex::within`]).

use rstar::{PointDistance, RTree, RTreeObject, AABB};

use crate::geometry::Point;

/// Relative size of the rounding margin added to every query radius: far above the few ulps
/// (≈ 1e-16 relative to the coordinates) by which a computed point–segment distance can differ
/// from the exact one, far below any length the contact search compares (its tolerance is
/// 1e-9 × the scene size).
const MARGIN: f64 = 1e-12;

/// One segment in the tree: its end points and its index in the caller's list.
struct Segment {
    a: Point,
    b: Point,
    index: usize,
}

impl RTreeObject for Segment {
    type Envelope = AABB<Point>;

    fn envelope(&self) -> Self::Envelope {
        AABB::from_corners(self.a, self.b)
    }
}

impl PointDistance for Segment {
    /// Squared distance from `p` to the segment (only orders the nearest-neighbour iteration).
    fn distance_2(&self, p: &Point) -> f64 {
        let (a, b) = (self.a, self.b);
        let d = [b[0] - a[0], b[1] - a[1]];
        let len2 = d[0] * d[0] + d[1] * d[1];
        let t = if len2 > 0.0 {
            (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (dx, dy) = (a[0] + t * d[0] - p[0], a[1] + t * d[1] - p[1]);
        dx * dx + dy * dy
    }
}

/// An R-tree over a list of segments `[a, b]` (node indices into a node list).
pub(super) struct SegmentIndex {
    tree: RTree<Segment>,
    /// Largest coordinate magnitude of the segments' end points (scales the rounding margin).
    magnitude: f64,
}

impl SegmentIndex {
    /// Indexes `segments` (pairs of indices into `nodes`); queries return positions in
    /// `segments`.  O(s log s).
    pub(super) fn new(nodes: &[Point], segments: &[[usize; 2]]) -> Self {
        let items: Vec<Segment> = segments
            .iter()
            .enumerate()
            .map(|(index, &[a, b])| Segment {
                a: nodes[a],
                b: nodes[b],
                index,
            })
            .collect();
        let magnitude = items
            .iter()
            .flat_map(|s| [s.a, s.b])
            .flatten()
            .fold(0.0_f64, |m, c| m.max(c.abs()));
        Self {
            tree: RTree::bulk_load(items),
            magnitude,
        }
    }

    /// Positions of the segments in (approximately) increasing distance from `p`; every segment
    /// comes exactly once.  Cheap for the first few, O(s log s) to exhaust.
    pub(super) fn nearest(&self, p: Point) -> impl Iterator<Item = usize> + '_ {
        self.tree.nearest_neighbor_iter(&p).map(|s| s.index)
    }

    /// Positions of (at least) every segment whose distance from `p`, as computed by
    /// [`crate::geometry::project_on_segment`] or any other rounding of the exact distance, is
    /// at most `r`: the segments whose boxes meet the square of half-side `r` plus a rounding
    /// margin around `p`.  In no particular order.
    pub(super) fn within(&self, p: Point, r: f64) -> impl Iterator<Item = usize> + '_ {
        let scale = self.magnitude.max(p[0].abs()).max(p[1].abs()).max(r);
        let h = r + MARGIN * scale;
        let query = AABB::from_corners([p[0] - h, p[1] - h], [p[0] + h, p[1] + h]);
        self.tree
            .locate_in_envelope_intersecting(&query)
            .map(|s| s.index)
    }

    /// True when no segment is indexed.
    pub(super) fn is_empty(&self) -> bool {
        self.tree.size() == 0
    }
}
