//! Cells in mesh numbering: none degenerate, all oriented one way (reoriented
//! counter-clockwise when all are clockwise), convex.

use super::nodes::Numbered;
use super::GmshProblem;
use crate::geometry::Point;

/// The cells (`cells_tags`: element tag and node tags) in mesh numbering, counter-clockwise.
pub(super) fn orient(
    numbered: &Numbered,
    cells_tags: &[(u64, Vec<u64>)],
) -> Result<Vec<Vec<usize>>, GmshProblem> {
    let (nodes, tol) = (&numbered.nodes, numbered.tol);
    let mut cells: Vec<Vec<usize>> = cells_tags
        .iter()
        .map(|(_, n)| n.iter().map(|t| numbered.index[t]).collect())
        .collect();
    let areas: Vec<f64> = cells.iter().map(|c| 0.5 * twice_area(nodes, c)).collect();
    let area_tol = tol * numbered.size;
    for (k, a) in areas.iter().enumerate() {
        if a.abs() <= area_tol {
            return Err(GmshProblem::Degenerate {
                element: cells_tags[k].0,
                area: *a,
            });
        }
    }
    let sign = orientation(&areas, cells_tags)?;
    for (k, c) in cells.iter().enumerate() {
        if !corners_agree(nodes, c, sign, tol * tol) {
            return Err(GmshProblem::Degenerate {
                element: cells_tags[k].0,
                area: areas[k],
            });
        }
    }
    if sign < 0.0 {
        for c in &mut cells {
            c.reverse();
        }
    }
    Ok(cells)
}

/// The sign of the majority of the cells' areas (1 on a tie); refuses a cell of the other.
fn orientation(areas: &[f64], cells_tags: &[(u64, Vec<u64>)]) -> Result<f64, GmshProblem> {
    let ccw = areas.iter().filter(|a| **a > 0.0).count();
    let cw = areas.len() - ccw;
    let sign = if ccw >= cw { 1.0 } else { -1.0 };
    if let Some(k) = areas.iter().position(|a| a.signum() != sign) {
        return Err(GmshProblem::Inverted {
            element: cells_tags[k].0,
            orientation: if areas[k] > 0.0 {
                "counter-clockwise"
            } else {
                "clockwise"
            },
            majority: ccw.max(cw),
            total: areas.len(),
        });
    }
    Ok(sign)
}

/// Twice the signed area of a polygon given by node indices.
fn twice_area(nodes: &[Point], cell: &[usize]) -> f64 {
    let n = cell.len();
    (0..n)
        .map(|i| {
            let (p, q) = (nodes[cell[i]], nodes[cell[(i + 1) % n]]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum()
}

/// True when every corner of the cell turns the same way as its area (convex, non-degenerate).
fn corners_agree(nodes: &[Point], cell: &[usize], sign: f64, tol: f64) -> bool {
    let n = cell.len();
    (0..n).all(|i| {
        let (a, b, c) = (
            nodes[cell[(i + n - 1) % n]],
            nodes[cell[i]],
            nodes[cell[(i + 1) % n]],
        );
        let cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
        sign * cross > tol
    })
}
