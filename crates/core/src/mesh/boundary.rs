//! Deterministic boundary discretisation (shared by P1 and Q1) and box/polygon crossings.
//!
//! Rule: on every polygon edge the break points are its two end vertices plus every given
//! break point lying on the edge (distance ≤ `tol`), sorted along the edge; each sub-interval
//! between consecutive break points is split evenly into `k = ceil(len / hmax − 1e-9)` pieces.
//! Sub-interval points are computed from the lexicographically smaller end point, so two bodies
//! that share a sub-interval compute the same points whatever their orientations.  With a graded
//! size field, sub-intervals where h < hmax somewhere are split by [`SizeField::split`] instead
//! (same end rule).

use crate::geometry::{distance, orient, project_on_segment, signed_area, Point};

use super::sizing::SizeField;
use super::MeshError;

/// Relative slack in `k = ceil(len / hmax − 1e-9)`.
const CEIL_SLACK: f64 = 1e-9;

/// The polygon with consecutive duplicate vertices (closer than `tol`) removed, oriented
/// counter-clockwise.  Errors when fewer than 3 distinct vertices or no area remain.
pub(crate) fn clean_polygon(polygon: &[Point], tol: f64) -> Result<Vec<Point>, MeshError> {
    if polygon.len() < 3 {
        return Err(MeshError::DegeneratePolygon {
            reason: format!("{} vertices, at least 3 needed", polygon.len()),
        });
    }
    if let Some(p) = polygon
        .iter()
        .find(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return Err(MeshError::DegeneratePolygon {
            reason: format!("vertex {p:?} is not finite"),
        });
    }
    let mut cleaned: Vec<Point> = Vec::with_capacity(polygon.len());
    for &p in polygon {
        if cleaned.last().is_none_or(|&q| distance(p, q) > tol) {
            cleaned.push(p);
        }
    }
    while cleaned.len() > 1 && distance(cleaned[0], cleaned[cleaned.len() - 1]) <= tol {
        cleaned.pop();
    }
    if cleaned.len() < 3 {
        return Err(MeshError::DegeneratePolygon {
            reason: "fewer than 3 distinct vertices".into(),
        });
    }
    let area = signed_area(&cleaned);
    let [x0, x1, y0, y1] = crate::geometry::bounding_box(&cleaned);
    let extent = (x1 - x0).max(y1 - y0);
    if area.is_nan() || area.abs() <= 1e-14 * extent * extent {
        return Err(MeshError::DegeneratePolygon {
            reason: format!("zero area (signed area {area:e})"),
        });
    }
    if area < 0.0 {
        cleaned.reverse();
    }
    Ok(cleaned)
}

/// Number of pieces of a sub-interval of length `len`.
pub(crate) fn pieces(len: f64, hmax: f64) -> usize {
    // `as` saturates; callers bound the total through `estimate_elements` first.
    ((len / hmax - CEIL_SLACK).ceil()).max(1.0) as usize
}

/// Break points of edge `a → b` in order from `a` (excluded) to `b` (excluded): the given
/// points within `tol` of the edge, projected onto it, without points within `tol` of each
/// other or of the ends.
fn edge_breaks(a: Point, b: Point, breakpoints: &[Point], tol: f64) -> Vec<Point> {
    let len = distance(a, b);
    let mut on_edge: Vec<(f64, Point)> = breakpoints
        .iter()
        .filter_map(|&p| {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return None;
            }
            let (t, d) = project_on_segment(p, a, b);
            if d > tol {
                return None;
            }
            let q = if orient(a, b, p) == 0.0 {
                p
            } else {
                [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
            };
            let s = t * len;
            (s > tol && s < len - tol).then_some((s, q))
        })
        .collect();
    on_edge.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut out: Vec<Point> = Vec::with_capacity(on_edge.len());
    let mut last = f64::NEG_INFINITY;
    for (s, q) in on_edge {
        if s - last > tol {
            out.push(q);
            last = s;
        }
    }
    out
}

/// Appends the points of sub-interval `p → q` to `out`: `p` and the `k − 1` interior points
/// (not `q`).  Where the size field is below `hmax` somewhere on the sub-interval, the graded
/// splitting of [`SizeField::split`] replaces the even one (computed from the lexicographically
/// smaller end, like it).
fn push_subinterval(out: &mut Vec<Point>, p: Point, q: Point, hmax: f64, field: &SizeField) {
    out.push(p);
    if !field.is_uniform() {
        let forward = (p[0], p[1]) <= (q[0], q[1]);
        let (a, b) = if forward { (p, q) } else { (q, p) };
        if let Some(mut points) = field.split(a, b) {
            if !forward {
                points.reverse();
            }
            out.extend(points);
            return;
        }
    }
    let k = pieces(distance(p, q), hmax);
    if k <= 1 {
        return;
    }
    let forward = (p[0], p[1]) <= (q[0], q[1]);
    let (a, b) = if forward { (p, q) } else { (q, p) };
    let kf = k as f64;
    let at = |i: usize| {
        let t = i as f64;
        [a[0] + (b[0] - a[0]) * t / kf, a[1] + (b[1] - a[1]) * t / kf]
    };
    if forward {
        out.extend((1..k).map(at));
    } else {
        out.extend((1..k).rev().map(at));
    }
}

/// The discretised boundary of a counter-clockwise polygon (as returned by [`clean_polygon`]),
/// as a closed counter-clockwise loop of distinct points (the last connects to the first).
/// `field` grades the sub-intervals it refines (a uniform field gives the even rule alone).
pub(crate) fn discretise(
    polygon: &[Point],
    hmax: f64,
    breakpoints: &[Point],
    tol: f64,
    field: &SizeField,
) -> Vec<Point> {
    let n = polygon.len();
    let mut out = Vec::new();
    for i in 0..n {
        let a = polygon[i];
        let b = polygon[(i + 1) % n];
        let mut prev = a;
        for q in edge_breaks(a, b, breakpoints, tol) {
            push_subinterval(&mut out, prev, q, hmax, field);
            prev = q;
        }
        push_subinterval(&mut out, prev, b, hmax, field);
    }
    out
}

/// Points where the edges of the closed box `region = [x1, x2, y1, y2]` cross or touch the
/// boundary of `polygon` (closed, either orientation), within the length tolerance `tol`.
///
/// A degenerate box is a segment (`x1 == x2` or `y1 == y2`) or a point (both).  Where a box edge
/// runs along a polygon edge, the ends of the overlap are reported.  Points are projected onto
/// the polygon edge they lie on, de-duplicated within `tol` and sorted by (x, y).  These are the
/// break points a caller passes to [`super::mesh_body`] so that a region's ends become nodes.
///
/// ```
/// use signorini_core::mesh::box_crossings;
/// let upper = [[0.0, 1.0], [2.0, 1.0], [2.0, 2.0], [0.0, 2.0]];
/// // A Neumann region on the top edge, x ∈ [1, 2]: its ends are (1, 2) and (2, 2).
/// let points = box_crossings(&upper, &[1.0, 2.0, 2.0, 2.0], 1e-9);
/// assert_eq!(points, vec![[1.0, 2.0], [2.0, 2.0]]);
/// ```
pub fn box_crossings(polygon: &[Point], region: &[f64; 4], tol: f64) -> Vec<Point> {
    let tol = if tol.is_finite() { tol.max(0.0) } else { 0.0 };
    if polygon.is_empty() || region.iter().any(|v| !v.is_finite()) {
        return Vec::new();
    }
    let [x1, x2, y1, y2] = *region;
    let (x1, x2) = (x1.min(x2), x1.max(x2));
    let (y1, y2) = (y1.min(y2), y1.max(y2));
    let flat_x = x2 - x1 <= tol;
    let flat_y = y2 - y1 <= tol;
    let sides: Vec<[Point; 2]> = match (flat_x, flat_y) {
        (true, true) => vec![[[x1, y1], [x1, y1]]],
        (true, false) => vec![[[x1, y1], [x1, y2]]],
        (false, true) => vec![[[x1, y1], [x2, y1]]],
        (false, false) => vec![
            [[x1, y1], [x2, y1]],
            [[x2, y1], [x2, y2]],
            [[x2, y2], [x1, y2]],
            [[x1, y2], [x1, y1]],
        ],
    };
    let n = polygon.len();
    let mut found: Vec<Point> = Vec::new();
    for i in 0..n {
        let (q1, q2) = (polygon[i], polygon[(i + 1) % n]);
        for &[p1, p2] in &sides {
            segment_crossings(p1, p2, q1, q2, tol, &mut found);
        }
    }
    found.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let mut out: Vec<Point> = Vec::with_capacity(found.len());
    for p in found {
        if out.iter().all(|&q| distance(p, q) > tol) {
            out.push(p);
        }
    }
    out
}

/// Pushes the points where segment p1–p2 (a box side, possibly a point) meets polygon edge
/// q1–q2, each on the polygon edge.
fn segment_crossings(p1: Point, p2: Point, q1: Point, q2: Point, tol: f64, out: &mut Vec<Point>) {
    let lq = distance(q1, q2);
    let lp = distance(p1, p2);
    let on_q = |p: Point| -> Option<Point> {
        let (t, d) = project_on_segment(p, q1, q2);
        (d <= tol).then(|| {
            if orient(q1, q2, p) == 0.0 {
                p
            } else {
                [q1[0] + t * (q2[0] - q1[0]), q1[1] + t * (q2[1] - q1[1])]
            }
        })
    };
    if lq <= tol {
        // A zero-length polygon edge: a touch when its point lies on the box side.
        if project_on_segment(q1, p1, p2).1 <= tol {
            out.push(q1);
        }
        return;
    }
    if lp <= tol {
        out.extend(on_q(p1));
        return;
    }
    let d1 = orient(q1, q2, p1) / lq;
    let d2 = orient(q1, q2, p2) / lq;
    if d1.abs() <= tol && d2.abs() <= tol {
        // Collinear: the ends of the overlap.
        out.extend(on_q(p1));
        out.extend(on_q(p2));
        for q in [q1, q2] {
            if project_on_segment(q, p1, p2).1 <= tol {
                out.push(q);
            }
        }
        return;
    }
    if d1.abs() <= tol {
        out.extend(on_q(p1));
    }
    if d2.abs() <= tol {
        out.extend(on_q(p2));
    }
    if (d1 > tol && d2 < -tol) || (d1 < -tol && d2 > tol) {
        let s = d1 / (d1 - d2);
        let x = [p1[0] + s * (p2[0] - p1[0]), p1[1] + s * (p2[1] - p1[1])];
        out.extend(on_q(x));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Refinement;

    fn field() -> SizeField {
        SizeField::new(
            0.2,
            &[Refinement {
                region: [0.9, 1.1, 0.9, 1.1],
                hmax: 0.01,
            }],
        )
    }

    /// A sub-interval's points do not depend on the direction it is walked in (the condition
    /// for conforming interfaces between bodies of opposite orientation).
    #[test]
    fn graded_subinterval_is_the_same_both_ways() {
        let f = field();
        let (p, q) = ([0.0, 1.0], [2.0, 1.0]);
        let mut forward = Vec::new();
        push_subinterval(&mut forward, p, q, 0.2, &f);
        let mut backward = Vec::new();
        push_subinterval(&mut backward, q, p, 0.2, &f);
        // forward = [p, interior…], backward = [q, interior reversed…].
        let mut a: Vec<Point> = forward[1..].to_vec();
        let mut b: Vec<Point> = backward[1..].to_vec();
        b.reverse();
        assert_eq!(a.len(), b.len());
        assert!(a.len() > 20, "{}", a.len());
        // Bit-identical, not just close.
        a.iter_mut().zip(&mut b).for_each(|(x, y)| assert_eq!(x, y));
    }

    /// A uniform field leaves the even rule untouched, bit for bit.
    #[test]
    fn uniform_field_gives_the_even_split() {
        let uniform = SizeField::new(0.2, &[]);
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let points = discretise(&square, 0.3, &[[0.5, 1.0]], 1e-9, &uniform);
        // 4 pieces on each full side (ceil(1 / 0.3)), 2 on each half of the top.
        assert_eq!(points.len(), 4 + 4 + 2 + 2 + 4);
        assert_eq!(points[1], [0.25, 0.0]);
    }

    /// Where the graded field equals hmax on a whole sub-interval, the even rule applies; a
    /// sub-interval through the box is split finer, every piece ≤ h at its midpoint.
    #[test]
    fn graded_discretisation_refines_near_the_box_only() {
        let f = field();
        let square = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.1], [0.0, 1.1]];
        let points = discretise(&square, 0.2, &[], 1e-9, &f);
        let n = points.len();
        let bottom: Vec<&Point> = points.iter().filter(|p| p[1] == 0.0).collect();
        // The bottom edge is 0.9 below the box: h = 0.01 + 0.25 · 0.9 = 0.235 > hmax: even,
        // 10 pieces of 0.2, 11 points with both corners.
        assert_eq!(bottom.len(), 11);
        assert!(bottom
            .iter()
            .all(|p| (p[0] / 0.2 - (p[0] / 0.2).round()).abs() < 1e-12));
        for i in 0..n {
            let (a, b) = (points[i], points[(i + 1) % n]);
            let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
            assert!(distance(a, b) <= f.at(mid) * (1.0 + 1e-9));
        }
        let top = points.iter().filter(|p| p[1] == 1.1).count();
        // The top edge runs along the box's top side for 0.2 at h 0.01: > 20 pieces.
        assert!(top > 30, "{top}");
    }
}
