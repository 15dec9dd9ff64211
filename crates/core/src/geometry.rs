//! Small plane-geometry predicates used by scene validation, meshing and contact search.

/// A point or vector in the plane.
pub type Point = [f64; 2];

/// Relative tolerance (× scene size) used to match regions and points to the geometry (the
/// scene's regions, a Gmsh mesh's groups).
pub const REGION_TOLERANCE: f64 = 1e-8;

/// Signed area of a polygon (positive when counter-clockwise).
pub fn signed_area(polygon: &[Point]) -> f64 {
    let n = polygon.len();
    (0..n)
        .map(|i| {
            let [x0, y0] = polygon[i];
            let [x1, y1] = polygon[(i + 1) % n];
            x0 * y1 - x1 * y0
        })
        .sum::<f64>()
        * 0.5
}

/// Axis-aligned bounding box `[xmin, xmax, ymin, ymax]` of a set of points.
pub fn bounding_box<'a>(points: impl IntoIterator<Item = &'a Point>) -> [f64; 4] {
    let mut b = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in points {
        b[0] = b[0].min(p[0]);
        b[1] = b[1].max(p[0]);
        b[2] = b[2].min(p[1]);
        b[3] = b[3].max(p[1]);
    }
    b
}

/// Cross product (b − a) × (c − a): twice the signed area of triangle a, b, c.
pub fn orient(a: Point, b: Point, c: Point) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The tangent of a contact row with unit normal `n`: n turned clockwise by a right angle.
pub fn tangent(n: Point) -> Point {
    [n[1], -n[0]]
}

/// Euclidean distance of two points.
pub fn distance(a: Point, b: Point) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Parameter t ∈ [0, 1] of the point on segment a–b closest to p, and the distance to it.
pub fn project_on_segment(p: Point, a: Point, b: Point) -> (f64, f64) {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = [a[0] + t * d[0], a[1] + t * d[1]];
    (t, distance(p, q))
}

/// True when the closed segments p1–p2 and q1–q2 share a point (`tol`: length tolerance).
pub fn segments_touch(p1: Point, p2: Point, q1: Point, q2: Point, tol: f64) -> bool {
    let lp = distance(p1, p2).max(tol);
    let lq = distance(q1, q2).max(tol);
    let d1 = orient(q1, q2, p1) / lq;
    let d2 = orient(q1, q2, p2) / lq;
    let d3 = orient(p1, p2, q1) / lp;
    let d4 = orient(p1, p2, q2) / lp;
    if ((d1 > tol && d2 < -tol) || (d1 < -tol && d2 > tol))
        && ((d3 > tol && d4 < -tol) || (d3 < -tol && d4 > tol))
    {
        return true;
    }
    project_on_segment(p1, q1, q2).1 <= tol
        || project_on_segment(p2, q1, q2).1 <= tol
        || project_on_segment(q1, p1, p2).1 <= tol
        || project_on_segment(q2, p1, p2).1 <= tol
}

/// One polygon edge in the R-tree of [`self_intersection`]: its bounding box enlarged by the
/// search margin, and its index.
struct EdgeBox {
    envelope: rstar::AABB<Point>,
    index: usize,
}

impl rstar::RTreeObject for EdgeBox {
    type Envelope = rstar::AABB<Point>;

    fn envelope(&self) -> Self::Envelope {
        self.envelope
    }
}

/// True when c and d lie on the same side of the line through a and b, both farther from it
/// than `slack`: then every point of c–d is farther than `slack` from the line, hence from a–b,
/// and no point of a–b is within `slack` of c–d — the pair cannot touch.  Cheap (no square
/// root): it spares [`segments_touch`] most candidate pairs of long, close, parallel edges.
fn strictly_beside(a: Point, b: Point, c: Point, d: Point, slack: f64) -> bool {
    let len2 = (b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2);
    let (oc, od) = (orient(a, b, c), orient(a, b, d));
    // |orient| / |ab| is the distance to the line: compare squares, |orient|² > slack² |ab|².
    let far = slack * slack * len2;
    len2 > 0.0 && oc.signum() == od.signum() && oc * oc > far && od * od > far
}

/// First pair of non-adjacent edges (i, j), i < j, in lexicographic order, of a closed polygon
/// that touch (`tol`: length tolerance, as in [`segments_touch`]); otherwise the first spike (two
/// adjacent edges folding back onto each other), as `(i, i + 1)`.  A simple polygon has neither.
/// Edge i runs from vertex i to vertex i + 1 (mod n); adjacent edges share a vertex there, which
/// is not an intersection.
///
/// Edges go into an R-tree of their bounding boxes enlarged by `tol` (plus a rounding margin):
/// two edges can touch only when their enlarged boxes overlap, so only those candidate pairs are
/// tested, with [`segments_touch`] exactly as a test of every pair would.  Cost: O(n log n) to
/// build and query the tree, plus one test per candidate pair — O(n) pairs when the edges are
/// short next to their distance to non-neighbouring edges (every polygon fine enough to mesh);
/// it grows towards n² only when many long, slanted edges have overlapping boxes (a star with
/// thousands of long spikes).  A polygon with a non-finite coordinate gives `None` (callers check
/// finiteness first).
///
/// ```
/// use signorini_core::geometry::self_intersection;
/// let bowtie = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
/// assert_eq!(self_intersection(&bowtie, 1e-12), Some((0, 2)));
/// let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
/// assert_eq!(self_intersection(&square, 1e-12), None);
/// ```
pub fn self_intersection(polygon: &[Point], tol: f64) -> Option<(usize, usize)> {
    let n = polygon.len();
    if polygon.iter().flatten().any(|c| !c.is_finite()) || !tol.is_finite() {
        return None;
    }
    if n >= 4 {
        // `segments_touch` accepts a pair when a point lies within `tol` of the other segment
        // (distances rounded to a few ulps of the coordinates) or when the segments cross; either
        // way their boxes enlarged by this margin overlap.
        let magnitude = polygon
            .iter()
            .flatten()
            .fold(0.0_f64, |m, c| m.max(c.abs()));
        let margin = tol.max(0.0) * (1.0 + 1e-9) + 1e-12 * magnitude;
        // Distance beyond which `strictly_beside` rules a pair out (again above `tol` by more
        // than any rounding of `segments_touch`'s own distances).
        let slack = tol.max(0.0) * (1.0 + 1e-6) + 1e-12 * magnitude;
        let boxes: Vec<EdgeBox> = (0..n)
            .map(|i| {
                let (a, b) = (polygon[i], polygon[(i + 1) % n]);
                EdgeBox {
                    envelope: rstar::AABB::from_corners(
                        [a[0].min(b[0]) - margin, a[1].min(b[1]) - margin],
                        [a[0].max(b[0]) + margin, a[1].max(b[1]) + margin],
                    ),
                    index: i,
                }
            })
            .collect();
        let envelopes: Vec<rstar::AABB<Point>> = boxes.iter().map(|e| e.envelope).collect();
        let tree = rstar::RTree::bulk_load(boxes);
        for (i, envelope) in envelopes.iter().enumerate() {
            let (a, b) = (polygon[i], polygon[(i + 1) % n]);
            let first = tree
                .locate_in_envelope_intersecting(envelope)
                .map(|e| e.index)
                .filter(|&j| j > i + 1 && !(i == 0 && j == n - 1))
                .filter(|&j| {
                    let (c, d) = (polygon[j], polygon[(j + 1) % n]);
                    !strictly_beside(a, b, c, d, slack)
                        && !strictly_beside(c, d, a, b, slack)
                        && segments_touch(a, b, c, d, tol)
                })
                .min();
            if let Some(j) = first {
                return Some((i, j));
            }
        }
    }
    // Adjacent edges folding back onto each other (a spike) also make a polygon non-simple.
    (0..n).find_map(|i| {
        let (a, b, c) = (polygon[i], polygon[(i + 1) % n], polygon[(i + 2) % n]);
        let ab = distance(a, b).max(tol);
        let bc = distance(b, c).max(tol);
        let collinear = orient(a, b, c).abs() / (ab * bc) <= 1e-12;
        let back = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]) < 0.0;
        (collinear && back).then_some((i, (i + 1) % n))
    })
}

/// True when `p` lies in the closed box `[x1, x2, y1, y2]` enlarged by `tol`.
pub fn in_box(p: Point, region: &[f64; 4], tol: f64) -> bool {
    p[0] >= region[0] - tol
        && p[0] <= region[1] + tol
        && p[1] >= region[2] - tol
        && p[1] <= region[3] + tol
}

/// The part of segment a–b inside the closed box `region` enlarged by `tol` (Liang–Barsky
/// clipping): `None` when they do not meet, otherwise the clipped length (possibly zero).
pub fn clip_to_box(a: Point, b: Point, region: &[f64; 4], tol: f64) -> Option<f64> {
    clip_parameters(a, b, region, tol).map(|(t0, t1)| (t1 - t0) * (b[0] - a[0]).hypot(b[1] - a[1]))
}

/// The end points of the part of segment a–b inside the closed box `region` enlarged by `tol`
/// (Liang–Barsky clipping), in the direction a → b; `None` when they do not meet.
///
/// ```
/// use signorini_core::geometry::clip_segment_to_box;
/// let clipped = clip_segment_to_box([0.0, 0.0], [4.0, 0.0], &[1.0, 2.0, -1.0, 1.0], 0.0);
/// assert_eq!(clipped, Some(([1.0, 0.0], [2.0, 0.0])));
/// ```
pub fn clip_segment_to_box(
    a: Point,
    b: Point,
    region: &[f64; 4],
    tol: f64,
) -> Option<(Point, Point)> {
    let d = [b[0] - a[0], b[1] - a[1]];
    clip_parameters(a, b, region, tol).map(|(t0, t1)| {
        (
            [a[0] + t0 * d[0], a[1] + t0 * d[1]],
            [a[0] + t1 * d[0], a[1] + t1 * d[1]],
        )
    })
}

/// Liang–Barsky parameters 0 ≤ t0 ≤ t1 ≤ 1 of the part of a–b inside the enlarged box.
fn clip_parameters(a: Point, b: Point, region: &[f64; 4], tol: f64) -> Option<(f64, f64)> {
    let d = [b[0] - a[0], b[1] - a[1]];
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    let checks = [
        (-d[0], a[0] - (region[0] - tol)),
        (d[0], (region[1] + tol) - a[0]),
        (-d[1], a[1] - (region[2] - tol)),
        (d[1], (region[3] + tol) - a[1]),
    ];
    for (p, q) in checks {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// Length of a closed polygon's boundary inside the box (`None` when they do not meet).
pub fn boundary_in_box(polygon: &[Point], region: &[f64; 4], tol: f64) -> Option<f64> {
    let n = polygon.len();
    (0..n)
        .filter_map(|i| clip_to_box(polygon[i], polygon[(i + 1) % n], region, tol))
        .reduce(|x, y| x + y)
}

/// True when `p` lies inside the polygon or on its boundary (within `tol`).
pub fn contains(polygon: &[Point], p: Point, tol: f64) -> bool {
    let n = polygon.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        if project_on_segment(p, a, b).1 <= tol {
            return true;
        }
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    inside
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn area_orientation_and_simplicity() {
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(signed_area(&square), 1.0);
        let mut cw = square;
        cw.reverse();
        assert_eq!(signed_area(&cw), -1.0);
        assert_eq!(self_intersection(&square, 1e-12), None);
        let bowtie = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(self_intersection(&bowtie, 1e-12).is_some());
        let spike = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        assert!(self_intersection(&spike, 1e-12).is_some());
    }

    #[test]
    fn clipping_and_containment() {
        let top = [[0.0, 2.0], [2.0, 2.0]];
        let l = clip_to_box(top[0], top[1], &[1.0, 2.0, 2.0, 2.0], 1e-12).unwrap();
        assert!((l - 1.0).abs() < 1e-9);
        assert_eq!(
            clip_to_box(top[0], top[1], &[3.0, 4.0, 2.0, 2.0], 1e-12),
            None
        );
        let point = clip_to_box(top[0], top[1], &[2.0, 3.0, 1.0, 3.0], 1e-12).unwrap();
        assert!(point < 1e-9);
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert!(contains(&square, [0.5, 0.5], 1e-12));
        assert!(contains(&square, [1.0, 0.5], 1e-12));
        assert!(!contains(&square, [1.5, 0.5], 1e-12));
        let edge = boundary_in_box(&square, &[0.0, 0.0, 0.0, 1.0], 1e-12).unwrap();
        assert!((edge - 1.0).abs() < 1e-9);
    }

    #[test]
    fn projection_onto_segment() {
        let (t, d) = project_on_segment([0.25, 1.0], [0.0, 0.0], [1.0, 0.0]);
        assert!((t - 0.25).abs() < 1e-15 && (d - 1.0).abs() < 1e-15);
    }
}
