//! Structured Q1 grids on axis-aligned rectangles.

use crate::geometry::{bounding_box, Point};

use super::boundary::{discretise, pieces};
use super::sizing::SizeField;
use super::{Cells, Mesh, MeshError};

/// The rectangle `[x0, x1] × [y0, y1]` when the counter-clockwise polygon is an axis-aligned
/// rectangle, possibly with extra vertices on its sides (within `tol`).
pub(crate) fn as_rectangle(polygon: &[Point], tol: f64) -> Option<[f64; 4]> {
    let b = bounding_box(polygon);
    let on_side = |p: &Point| {
        (p[0] - b[0]).abs() <= tol
            || (p[0] - b[1]).abs() <= tol
            || (p[1] - b[2]).abs() <= tol
            || (p[1] - b[3]).abs() <= tol
    };
    if !polygon.iter().all(on_side) {
        return None;
    }
    // Every edge must be horizontal or vertical and run along a side of the box.
    let n = polygon.len();
    for i in 0..n {
        let (p, q) = (polygon[i], polygon[(i + 1) % n]);
        let horizontal = (p[1] - q[1]).abs() <= tol
            && ((p[1] - b[2]).abs() <= tol || (p[1] - b[3]).abs() <= tol);
        let vertical = (p[0] - q[0]).abs() <= tol
            && ((p[0] - b[0]).abs() <= tol || (p[0] - b[1]).abs() <= tol);
        if !(horizontal || vertical) {
            return None;
        }
    }
    // All four corners must be vertices, and the polygon area the box area.
    let corners = [[b[0], b[2]], [b[1], b[2]], [b[1], b[3]], [b[0], b[3]]];
    let has = |c: Point| {
        polygon
            .iter()
            .any(|p| (p[0] - c[0]).abs() <= tol && (p[1] - c[1]).abs() <= tol)
    };
    if !corners.iter().all(|&c| has(c)) {
        return None;
    }
    let area = crate::geometry::signed_area(polygon);
    let box_area = (b[1] - b[0]) * (b[3] - b[2]);
    if (area - box_area).abs() > 1e-9 * box_area {
        return None;
    }
    Some(b)
}

/// The x and y lines of the graded grid on the rectangle `b` (see [`mesh_rectangle`]).
pub(crate) fn graded_grid(
    polygon: &[Point],
    hmax: f64,
    field: &SizeField,
    breakpoints: &[Point],
    b: &[f64; 4],
    tol: f64,
) -> (Vec<f64>, Vec<f64>) {
    let (bx, by) = grid_breaks(polygon, breakpoints, field, b, tol);
    (
        graded_ticks(&bx, hmax, &field.along_x(b, tol)),
        graded_ticks(&by, hmax, &field.along_y(b, tol)),
    )
}

/// Break values of a graded grid on the rectangle `b`: x of the vertices and break points on
/// the bottom and top sides and of the refined boxes' sides, y of those on the left and right
/// sides and of the boxes' sides (ends included, sorted, de-duplicated within `tol`, ends
/// pinned to the box), so every refined box inside the rectangle is a union of cells.
fn grid_breaks(
    polygon: &[Point],
    breakpoints: &[Point],
    field: &SizeField,
    b: &[f64; 4],
    tol: f64,
) -> (Vec<f64>, Vec<f64>) {
    let mut xs = vec![b[0], b[1]];
    let mut ys = vec![b[2], b[3]];
    let inside = |v: f64, lo: f64, hi: f64| v >= lo - tol && v <= hi + tol;
    for p in polygon.iter().chain(breakpoints) {
        if !(p[0].is_finite() && p[1].is_finite()) {
            continue;
        }
        let on_x_side = (p[1] - b[2]).abs() <= tol || (p[1] - b[3]).abs() <= tol;
        if on_x_side && inside(p[0], b[0], b[1]) {
            xs.push(p[0].clamp(b[0], b[1]));
        }
        let on_y_side = (p[0] - b[0]).abs() <= tol || (p[0] - b[1]).abs() <= tol;
        if on_y_side && inside(p[1], b[2], b[3]) {
            ys.push(p[1].clamp(b[2], b[3]));
        }
    }
    // A box side closer than half its region's size to another break value (a side, a vertex,
    // another body's corner) would only make a sliver row or column: skipped, for every body
    // alike (they see the same break values on a shared edge), so interfaces stay conforming.
    let with_sides = |mut v: Vec<f64>, axis: usize| {
        let sides: Vec<f64> = field
            .region_sides(axis)
            .filter(|&(t, h)| v.iter().all(|&w| (t - w).abs() >= 0.5 * h))
            .map(|(t, _)| t)
            .collect();
        v.extend(sides);
        v
    };
    let (xs, ys) = (with_sides(xs, 0), with_sides(ys, 1));
    let pin = |mut v: Vec<f64>, lo: f64, hi: f64| {
        v.retain(|&t| t == lo || t == hi || (t - lo > tol && hi - t > tol));
        merged(v, tol)
    };
    (pin(xs, b[0], b[1]), pin(ys, b[2], b[3]))
}

/// Sorted, de-duplicated (within `tol`) values.
fn merged(mut values: Vec<f64>, tol: f64) -> Vec<f64> {
    values.sort_by(f64::total_cmp);
    let mut out: Vec<f64> = Vec::with_capacity(values.len());
    for v in values {
        if out.last().is_none_or(|&w| v - w > tol) {
            out.push(v);
        }
    }
    out
}

/// Graded grid lines of one axis: each interval between consecutive `breaks` (sorted,
/// de-duplicated, ends included) split by the 1D field `field` (evaluated at `[t, 0]`), from its
/// smaller end; intervals where the field is `hmax` throughout split evenly as on the boundary.
pub(crate) fn graded_ticks(breaks: &[f64], hmax: f64, field: &SizeField) -> Vec<f64> {
    let mut out = Vec::new();
    for w in breaks.windows(2) {
        let (a, b) = (w[0], w[1]);
        out.push(a);
        match field.split([a, 0.0], [b, 0.0]) {
            Some(points) => out.extend(points.iter().map(|p| p[0])),
            None => {
                let k = pieces(b - a, hmax);
                out.extend((1..k).map(|i| a + (b - a) * i as f64 / k as f64));
            }
        }
    }
    if let Some(&last) = breaks.last() {
        out.push(last);
    }
    out
}

/// Structured Q1 mesh of a counter-clockwise axis-aligned rectangle polygon.
///
/// x-coordinates: the union of the boundary split points on the bottom and top sides; y: the
/// union of those on the left and right sides.  Nodes are numbered row by row from the bottom
/// left (`j · nx + i`), quads counter-clockwise.
///
/// Graded (`field` not uniform): a tensor grid whose x lines split each interval between the x
/// break values (polygon vertices and break points on the bottom and top sides) by the 1D field
/// [`SizeField::along_x`] (h's minimum over the grid column), y likewise, so every cell side is
/// ≤ h everywhere in its cell's column or row.
pub(crate) fn mesh_rectangle(
    polygon: &[Point],
    hmax: f64,
    field: &SizeField,
    breakpoints: &[Point],
    tol: f64,
) -> Result<Mesh, MeshError> {
    let b = as_rectangle(polygon, tol).ok_or(MeshError::NotARectangle)?;
    let (mut xs, mut ys) = if field.is_uniform() {
        let boundary = discretise(polygon, hmax, breakpoints, tol, field);
        let mut xs = Vec::new();
        let mut ys = Vec::new();
        for p in &boundary {
            if (p[1] - b[2]).abs() <= tol || (p[1] - b[3]).abs() <= tol {
                xs.push(p[0]);
            }
            if (p[0] - b[0]).abs() <= tol || (p[0] - b[1]).abs() <= tol {
                ys.push(p[1]);
            }
        }
        (merged(xs, tol), merged(ys, tol))
    } else {
        graded_grid(polygon, hmax, field, breakpoints, &b, tol)
    };
    // Pin the ends to the exact box (the corners are polygon vertices).
    if let Some(first) = xs.first_mut() {
        *first = b[0];
    }
    if let Some(last) = xs.last_mut() {
        *last = b[1];
    }
    if let Some(first) = ys.first_mut() {
        *first = b[2];
    }
    if let Some(last) = ys.last_mut() {
        *last = b[3];
    }
    let (nx, ny) = (xs.len(), ys.len());
    if nx < 2 || ny < 2 {
        return Err(MeshError::DegeneratePolygon {
            reason: "rectangle thinner than the tolerance".into(),
        });
    }
    let mut nodes = Vec::with_capacity(nx * ny);
    for &y in &ys {
        for &x in &xs {
            nodes.push([x, y]);
        }
    }
    let id = |i: usize, j: usize| j * nx + i;
    let mut quads = Vec::with_capacity((nx - 1) * (ny - 1));
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mut edges = Vec::with_capacity(2 * (nx + ny));
    edges.extend((0..nx - 1).map(|i| [id(i, 0), id(i + 1, 0)]));
    edges.extend((0..ny - 1).map(|j| [id(nx - 1, j), id(nx - 1, j + 1)]));
    edges.extend((1..nx).rev().map(|i| [id(i, ny - 1), id(i - 1, ny - 1)]));
    edges.extend((1..ny).rev().map(|j| [id(0, j), id(0, j - 1)]));
    Ok(Mesh {
        nodes,
        cells: Cells::Quads(quads),
        boundary: edges,
    })
}
