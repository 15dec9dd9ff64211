//! The arc-length coordinate `s` of the slave nodes of a contact pair along the slave interface
//! (`result.json`'s `contacts[].nodes[].s` and `piece`, the abscissa of `pressure.svg`).
//!
//! **The interface** of a pair is the set of its slave nodes that have a row, joined by the
//! slave's boundary edges whose two ends both have a row.  Its connected parts are the
//! **pieces**: usually one chain of boundary edges; several when the rows fall on disjoint
//! stretches of the slave boundary (a punch with two feet), a closed loop when every node of a
//! boundary loop has a row, a lone node when a row's node has no neighbour with a row.
//!
//! **Direction.**  The *axis* of the pair is x when the bounding box of its row nodes is at least
//! as wide as it is tall, y otherwise.  A chain starts at the one of its two ends with the smaller
//! coordinate along the axis (ties: the smaller other coordinate, then the smaller node index),
//! so `s` runs left to right along a mostly horizontal interface and bottom to top along a mostly
//! vertical one.  A closed loop starts at its node of smallest coordinate along the axis (same
//! ties) and runs in the slave boundary's own (counter-clockwise) direction.
//!
//! **Value.**  Walking each piece from its start, `s` grows by the straight distance between
//! consecutive nodes of the walk: along a chain of boundary edges that is the arc length of the
//! polygonal interface.  The pieces are laid end to end in the order of their starts' coordinate
//! along the axis (ties as above): the first piece starts at `s = 0`, each later one at the end
//! of the previous one plus the straight distance from that end to its own start (for pieces on
//! one straight line, `s` is then the distance from the first start along the line).  Every
//! node of piece `k` (0-based, in that order) reports `piece = k`.
//!
//! (A boundary node on more than two interface edges — a boundary touching itself at a vertex —
//! makes a branching piece; the walk then continues from the unvisited node nearest to where it
//! got stuck, in straight distance, and `s` still grows by the straight distance between
//! consecutive nodes.)

use std::cmp::Ordering;

use crate::geometry::{self, Point};
use crate::mesh::Mesh;

/// Where one slave node lies along its pair's interface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcPosition {
    /// The interface piece (0-based, in the order of the module docs).
    pub piece: usize,
    /// Arc-length coordinate from the start of the first piece, in the scene's length unit.
    pub s: f64,
}

/// The arc positions of `nodes` (slave node indices of `mesh`, one per contact row, in row
/// order; a node listed twice gets the same position twice), as defined in the module docs.
/// Indices outside the mesh get `piece = usize::MAX` and `s = NaN` (they cannot occur in a
/// model built by [`crate::contact::contact_rows`]).
pub fn interface_arc(mesh: &Mesh, nodes: &[usize]) -> Vec<ArcPosition> {
    let n = mesh.nodes.len();
    // Distinct row nodes, in a dense numbering.
    let mut local = vec![usize::MAX; n];
    let mut members: Vec<usize> = Vec::new();
    for &v in nodes {
        if v < n && local[v] == usize::MAX {
            local[v] = members.len();
            members.push(v);
        }
    }
    let m = members.len();
    let point = |i: usize| mesh.nodes[members[i]];
    // Interface edges, oriented as the boundary (body on the left), without repeats.
    let mut adjacency: Vec<Vec<usize>> = vec![Vec::new(); m];
    let mut forward: Vec<Vec<usize>> = vec![Vec::new(); m];
    for &[a, b] in &mesh.boundary {
        if a >= n || b >= n || a == b {
            continue;
        }
        let (la, lb) = (local[a], local[b]);
        if la == usize::MAX || lb == usize::MAX || adjacency[la].contains(&lb) {
            continue;
        }
        adjacency[la].push(lb);
        adjacency[lb].push(la);
        forward[la].push(lb);
    }
    // The axis and the order along it.
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for i in 0..m {
        let p = point(i);
        lo = [lo[0].min(p[0]), lo[1].min(p[1])];
        hi = [hi[0].max(p[0]), hi[1].max(p[1])];
    }
    let axis = usize::from(hi[1] - lo[1] > hi[0] - lo[0]);
    let before = |i: usize, j: usize| -> Ordering {
        let (p, q) = (point(i), point(j));
        p[axis]
            .total_cmp(&q[axis])
            .then(p[1 - axis].total_cmp(&q[1 - axis]))
            .then(members[i].cmp(&members[j]))
    };
    // Pieces: connected components, each with its start.
    let mut component = vec![usize::MAX; m];
    let mut pieces: Vec<(usize, Vec<usize>)> = Vec::new();
    for seed in 0..m {
        if component[seed] != usize::MAX {
            continue;
        }
        let id = pieces.len();
        let mut stack = vec![seed];
        let mut all = Vec::new();
        component[seed] = id;
        while let Some(v) = stack.pop() {
            all.push(v);
            for &w in &adjacency[v] {
                if component[w] == usize::MAX {
                    component[w] = id;
                    stack.push(w);
                }
            }
        }
        let ends: Vec<usize> = all
            .iter()
            .copied()
            .filter(|&v| adjacency[v].len() <= 1)
            .collect();
        let pool = if ends.is_empty() { &all } else { &ends };
        let start = pool
            .iter()
            .copied()
            .min_by(|&i, &j| before(i, j))
            .unwrap_or(seed);
        pieces.push((start, all));
    }
    pieces.sort_by(|a, b| before(a.0, b.0));
    // Walk every piece.
    let mut position = vec![
        ArcPosition {
            piece: usize::MAX,
            s: f64::NAN,
        };
        m
    ];
    let mut visited = vec![false; m];
    let mut s = 0.0;
    let mut last: Option<usize> = None;
    for (k, (start, all)) in pieces.iter().enumerate() {
        let mut current = *start;
        let mut remaining = all.len();
        loop {
            if let Some(prev) = last {
                s += geometry::distance(point(prev), point(current));
            }
            visited[current] = true;
            position[current] = ArcPosition { piece: k, s };
            last = Some(current);
            remaining -= 1;
            if remaining == 0 {
                break;
            }
            // Next: an unvisited neighbour, the boundary's own successor first (it decides the
            // direction of a closed loop; a chain end has one neighbour only); when stuck, the
            // nearest unvisited node of the piece.
            let next = forward[current]
                .iter()
                .chain(&adjacency[current])
                .copied()
                .find(|&w| !visited[w])
                .or_else(|| {
                    let here: Point = point(current);
                    all.iter()
                        .copied()
                        .filter(|&w| !visited[w])
                        .min_by(|&i, &j| {
                            geometry::distance(here, point(i))
                                .total_cmp(&geometry::distance(here, point(j)))
                                .then(before(i, j))
                        })
                });
            match next {
                Some(w) => current = w,
                None => break,
            }
        }
    }
    nodes
        .iter()
        .map(|&v| {
            if v < n {
                position[local[v]]
            } else {
                ArcPosition {
                    piece: usize::MAX,
                    s: f64::NAN,
                }
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn a_flat_bottom_runs_left_to_right_in_row_order_whatever_the_node_numbering() {
        // The bottom of a block (counter-clockwise: left to right along y = 0) with nodes at
        // x = 0, 0.3, 1, 1.5, then the top; rows listed in a scrambled order.
        let mesh = Mesh::boundary_loop(vec![
            [0.0, 0.0],
            [0.3, 0.0],
            [1.0, 0.0],
            [1.5, 0.0],
            [1.5, 1.0],
            [0.0, 1.0],
        ]);
        let arc = interface_arc(&mesh, &[2, 0, 3, 1]);
        let s: Vec<f64> = arc.iter().map(|a| a.s).collect();
        // s is x here: the nodes' x coordinates, exactly (sums of exactly representable
        // lengths 0.3 + 0.7 rounded once each: compare to 1 ulp-level 1e-15).
        for (got, want) in s.iter().zip([1.0, 0.0, 1.5, 0.3]) {
            assert!((got - want).abs() < 1e-15, "{s:?}");
        }
        assert!(arc.iter().all(|a| a.piece == 0));
    }

    #[test]
    fn a_top_surface_runs_left_to_right_against_the_boundary_direction() {
        // The top of a foundation runs right to left counter-clockwise; s still starts at the
        // left end.
        let mesh = Mesh::boundary_loop(vec![
            [0.0, -1.0],
            [2.0, -1.0],
            [2.0, 0.0],
            [1.0, 0.0],
            [0.0, 0.0],
        ]);
        let arc = interface_arc(&mesh, &[2, 3, 4]);
        assert_eq!(arc.iter().map(|a| a.s).collect::<Vec<_>>(), [2.0, 1.0, 0.0]);
    }

    #[test]
    fn a_curved_interface_measures_arc_length_along_its_chords() {
        // Nodes on a half circle of radius 1 below its centre (0, 1), every 15°: the chain's
        // length is 12 chords of 2 sin(7.5°), computed here independently.
        let k = 12;
        let mut pts: Vec<Point> = (0..=k)
            .map(|i| {
                let a = -std::f64::consts::PI + std::f64::consts::PI * f64::from(i) / f64::from(k);
                [a.cos(), 1.0 + a.sin()]
            })
            .collect();
        pts.push([0.0, 2.0]); // close the loop above
        let mesh = Mesh::boundary_loop(pts);
        let rows: Vec<usize> = (0..=12).rev().collect();
        let arc = interface_arc(&mesh, &rows);
        let chord = 2.0 * (std::f64::consts::PI / 24.0).sin();
        for (r, a) in rows.iter().zip(&arc) {
            // Node 0 is at x = −1 (the left end): s = r chords.  12 additions of one chord:
            // round-off below 1e-14.
            assert!((a.s - *r as f64 * chord).abs() < 1e-14, "{r}: {}", a.s);
        }
    }

    #[test]
    fn disjoint_pieces_are_laid_end_to_end_with_the_straight_jump_between_them() {
        // A punch with two feet: bottom edges [0, 1] and [2, 3] at y = 0, joined through the
        // body above (not rows).  s equals x on both feet.
        let mesh = Mesh::boundary_loop(vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [2.0, 1.0],
            [2.0, 0.0],
            [3.0, 0.0],
            [3.0, 2.0],
            [0.0, 2.0],
        ]);
        let arc = interface_arc(&mesh, &[5, 4, 1, 0]);
        assert_eq!(
            arc,
            [
                ArcPosition { piece: 1, s: 3.0 },
                ArcPosition { piece: 1, s: 2.0 },
                ArcPosition { piece: 0, s: 1.0 },
                ArcPosition { piece: 0, s: 0.0 },
            ]
        );
    }

    #[test]
    fn a_vertical_interface_runs_bottom_to_top_and_a_closed_loop_counter_clockwise() {
        // Right side of a unit square: nodes 1 (1, 0), 2 (1, 0.5), 3 (1, 1).
        let mesh = Mesh::boundary_loop(vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 0.5],
            [1.0, 1.0],
            [0.0, 1.0],
        ]);
        let arc = interface_arc(&mesh, &[3, 2, 1]);
        assert_eq!(arc.iter().map(|a| a.s).collect::<Vec<_>>(), [1.0, 0.5, 0.0]);
        // The whole loop: starts at (0, 0) (smallest x, then y), runs counter-clockwise.
        let all = interface_arc(&mesh, &[0, 1, 2, 3, 4]);
        assert_eq!(
            all.iter().map(|a| a.s).collect::<Vec<_>>(),
            [0.0, 1.0, 1.5, 2.0, 3.0]
        );
        // A lone node is a piece of its own at s = 0.
        assert_eq!(
            interface_arc(&mesh, &[2]),
            [ArcPosition { piece: 0, s: 0.0 }]
        );
    }
}
