//! Interior seed points: an equilateral triangular lattice clipped to the polygon, kept away
//! from the boundary.  Seeding makes the interior mesh uniform and lets the Delaunay bulk loader
//! do most of the work instead of one-by-one refinement insertions.

use crate::geometry::Point;

/// Lattice points (rows `y = j r`, `r = s √3 / 2`, odd rows shifted by `s / 2`, anchored at the
/// origin) strictly inside the closed loop `boundary` and at distance ≥ `gap` from every
/// boundary segment.  Deterministic: depends only on the inputs, in row-major order.
pub(crate) fn lattice_points(boundary: &[Point], spacing: f64, gap: f64) -> Vec<Point> {
    lattice_points_in(boundary, spacing, gap, None, |_| true)
}

/// As [`lattice_points`], restricted to the points inside `window` (`[x1, x2, y1, y2]`, `None`:
/// everywhere) for which `keep` holds; only the window's rows and columns are visited.
pub(crate) fn lattice_points_in(
    boundary: &[Point],
    spacing: f64,
    gap: f64,
    window: Option<[f64; 4]>,
    keep: impl Fn(Point) -> bool,
) -> Vec<Point> {
    let n = boundary.len();
    if n < 3 || !(spacing.is_finite() && spacing > 0.0) {
        return Vec::new();
    }
    let row = spacing * 3f64.sqrt() / 2.0;
    let [_, _, y0, y1] = crate::geometry::bounding_box(boundary);
    let mut first = (y0 / row).ceil() as i64;
    let mut last = (y1 / row).floor() as i64;
    if let Some(w) = window {
        if !(w[2] <= w[3] && w[0] <= w[1]) {
            return Vec::new();
        }
        first = first.max((w[2] / row).ceil() as i64);
        last = last.min((w[3] / row).floor() as i64);
    }
    if last < first {
        return Vec::new();
    }
    let rows = (last - first + 1) as usize;
    let row_of = |y: f64| ((y / row).floor() as i64 - first).clamp(-1, rows as i64);

    // Segments crossing each row (half-open rule), for the inside test.
    let mut crossing: Vec<Vec<u32>> = vec![Vec::new(); rows];
    // Grid of cells (size `spacing`) → segments within `gap` of the cell, for the distance test.
    let cell = spacing;
    let [x0, _, _, _] = crate::geometry::bounding_box(boundary);
    let cell_of = |p: f64, origin: f64| ((p - origin) / cell).floor() as i64;
    let mut near: Vec<(i64, i64, u32)> = Vec::new();
    for i in 0..n {
        let (p, q) = (boundary[i], boundary[(i + 1) % n]);
        let (lo, hi) = (p[1].min(q[1]), p[1].max(q[1]));
        for r in row_of(lo).max(0)..=row_of(hi).min(rows as i64 - 1) {
            let y = (r + first) as f64 * row;
            if (p[1] <= y) != (q[1] <= y) {
                crossing[r as usize].push(i as u32);
            }
        }
        let (mut cx0, mut cx1) = (
            cell_of(p[0].min(q[0]) - gap, x0),
            cell_of(p[0].max(q[0]) + gap, x0),
        );
        let (mut cy0, mut cy1) = (cell_of(lo - gap, y0), cell_of(hi + gap, y0));
        if let Some(w) = window {
            // Only the cells of the window's points are ever looked up.
            cx0 = cx0.max(cell_of(w[0], x0));
            cx1 = cx1.min(cell_of(w[1], x0));
            cy0 = cy0.max(cell_of(w[2], y0));
            cy1 = cy1.min(cell_of(w[3], y0));
        }
        for cx in cx0..=cx1 {
            for cy in cy0..=cy1 {
                near.push((cx, cy, i as u32));
            }
        }
    }
    near.sort_unstable();

    let gap2 = gap * gap;
    let far_enough = |p: Point| {
        let key = (cell_of(p[0], x0), cell_of(p[1], y0));
        let start = near.partition_point(|&(a, b, _)| (a, b) < key);
        near[start..]
            .iter()
            .take_while(|&&(a, b, _)| (a, b) == key)
            .all(|&(_, _, i)| {
                let i = i as usize;
                distance2_to_segment(p, boundary[i], boundary[(i + 1) % n]) >= gap2
            })
    };

    let mut points = Vec::new();
    let mut xs: Vec<f64> = Vec::new();
    for (r, segments) in crossing.iter().enumerate() {
        let j = r as i64 + first;
        let y = j as f64 * row;
        xs.clear();
        xs.extend(segments.iter().map(|&i| {
            let (p, q) = (boundary[i as usize], boundary[(i as usize + 1) % n]);
            p[0] + (y - p[1]) / (q[1] - p[1]) * (q[0] - p[0])
        }));
        xs.sort_by(f64::total_cmp);
        let shift = if j.rem_euclid(2) == 1 {
            0.5 * spacing
        } else {
            0.0
        };
        for pair in xs.chunks_exact(2) {
            let (mut a, mut b) = (pair[0] + gap, pair[1] - gap);
            if let Some(w) = window {
                a = a.max(w[0]);
                b = b.min(w[1]);
            }
            if a > b {
                continue;
            }
            let k0 = ((a - shift) / spacing).ceil() as i64;
            let k1 = ((b - shift) / spacing).floor() as i64;
            for k in k0..=k1 {
                let p = [k as f64 * spacing + shift, y];
                if far_enough(p) && keep(p) {
                    points.push(p);
                }
            }
        }
    }
    points
}

/// Squared distance from `p` to segment a–b.
fn distance2_to_segment(p: Point, a: Point, b: Point) -> f64 {
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
