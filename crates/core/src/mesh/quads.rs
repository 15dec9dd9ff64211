//! Structured Q1 grids on axis-aligned rectangles.

use crate::geometry::{bounding_box, Point};

use super::boundary::discretise;
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

/// Structured Q1 mesh of a counter-clockwise axis-aligned rectangle polygon.
///
/// x-coordinates: the union of the boundary split points on the bottom and top sides; y: the
/// union of those on the left and right sides.  Nodes are numbered row by row from the bottom
/// left (`j · nx + i`), quads counter-clockwise.
pub(crate) fn mesh_rectangle(
    polygon: &[Point],
    hmax: f64,
    breakpoints: &[Point],
    tol: f64,
) -> Result<Mesh, MeshError> {
    let b = as_rectangle(polygon, tol).ok_or(MeshError::NotARectangle)?;
    let boundary = discretise(polygon, hmax, breakpoints, tol);
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
    let mut xs = merged(xs, tol);
    let mut ys = merged(ys, tol);
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
