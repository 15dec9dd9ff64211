//! Spatial index of boundary segments for the contact search: an R-tree (rstar) over the
//! segments' bounding boxes.
//!
//! Every query here is used the same way: the index only *narrows* the set of segments a
//! brute-force scan would look at, and the caller then evaluates the narrowed set with exactly
//! the arithmetic of the scan, in the scan's order.  The index never computes a distance that
//! reaches a result.  So the results are bit-identical to the scan as long as the narrowed set
//! holds every segment that could change the result — which the queries guarantee with a
//! rounding margin ([`SegmentIndex::within`]).

use rstar::{PointDistance, RTree, RTreeObject, SelectionFunction, AABB};

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
    /// Bounding box of every segment `[xmin, xmax, ymin, ymax]`.
    bounds: [f64; 4],
}

/// A cone with its apex pulled back: the points z with (z − apex)·axis ≥ cos |z − apex| − slack,
/// cut to the disc |z − apex| ≤ radius.  Where a facing segment that a slave node is not behind
/// can lie (see `Probe::cone` in the parent module).
pub(super) struct Cone {
    /// The slave node.
    pub(super) apex: Point,
    /// The slave's outward unit normal.
    pub(super) axis: Point,
    /// Cosine of the cone's half-angle.
    pub(super) cos: f64,
    /// How far behind the apex the cone reaches (length).
    pub(super) slack: f64,
    /// Radius of the disc.
    pub(super) radius: f64,
    /// Rounding margin (length), added to `slack` and `radius`.
    pub(super) margin: f64,
}

impl Cone {
    /// False only when no point of the box `[lower, upper]` lies in the cone: an upper bound of
    /// (z − apex)·axis − cos |z − apex| over the box (the linear part at its best corner, the
    /// distance at its nearest point) is below −slack, or the box is beyond the disc.
    fn may_meet(&self, lower: Point, upper: Point) -> bool {
        let mut linear = 0.0;
        let mut nearest2 = 0.0;
        for k in 0..2 {
            let (lo, hi) = (lower[k] - self.apex[k], upper[k] - self.apex[k]);
            linear += (self.axis[k] * lo).max(self.axis[k] * hi);
            let gap = if lo > 0.0 {
                lo
            } else if hi < 0.0 {
                -hi
            } else {
                0.0
            };
            nearest2 += gap * gap;
        }
        let nearest = nearest2.sqrt();
        nearest <= self.radius + self.margin
            && linear - self.cos * nearest >= -(self.slack + self.margin)
    }
}

impl SelectionFunction<Segment> for &Cone {
    fn should_unpack_parent(&self, envelope: &AABB<Point>) -> bool {
        self.may_meet(envelope.lower(), envelope.upper())
    }

    fn should_unpack_leaf(&self, leaf: &Segment) -> bool {
        let e = leaf.envelope();
        self.may_meet(e.lower(), e.upper())
    }
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
        let bounds = crate::geometry::bounding_box(items.iter().flat_map(|s| [&s.a, &s.b]));
        Self {
            tree: RTree::bulk_load(items),
            magnitude,
            bounds,
        }
    }

    /// Positions of the segments in (approximately) increasing distance from `p`, with that
    /// distance; every segment comes exactly once.  Cheap for the first few, O(s log s) to
    /// exhaust.
    pub(super) fn nearest(&self, p: Point) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.tree
            .nearest_neighbor_iter_with_distance_2(&p)
            .map(|(s, d2)| (s.index, d2.sqrt()))
    }

    /// Positions of (at least) every segment with a point in `cone`, in no particular order.
    pub(super) fn in_cone<'a>(&'a self, cone: &'a Cone) -> impl Iterator<Item = usize> + 'a {
        self.tree
            .locate_with_selection_function(cone)
            .map(|s| s.index)
    }

    /// An upper bound of the distance from `p` to any indexed segment (to the farthest corner
    /// of their bounding box).
    pub(super) fn farthest(&self, p: Point) -> f64 {
        let [x0, x1, y0, y1] = self.bounds;
        let dx = (p[0] - x0).abs().max((p[0] - x1).abs());
        let dy = (p[1] - y0).abs().max((p[1] - y1).abs());
        dx.hypot(dy)
    }

    /// The rounding margin of queries around `p` reaching `r`.
    pub(super) fn margin(&self, p: Point, r: f64) -> f64 {
        MARGIN * self.magnitude.max(p[0].abs()).max(p[1].abs()).max(r)
    }

    /// Positions of (at least) every segment whose distance from `p`, as computed by
    /// [`crate::geometry::project_on_segment`] or any other rounding of the exact distance, is
    /// at most `r`: the segments whose boxes meet the square of half-side `r` plus a rounding
    /// margin around `p`.  In no particular order.
    pub(super) fn within(&self, p: Point, r: f64) -> impl Iterator<Item = usize> + '_ {
        let h = r + self.margin(p, r);
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
