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
    let interface = Interface::new(mesh, nodes);
    let pieces = interface.pieces();
    let position = interface.walk(&pieces);
    nodes
        .iter()
        .map(|&v| {
            if v < interface.local.len() {
                position[interface.local[v]]
            } else {
                UNPLACED
            }
        })
        .collect()
}

/// The position of a node outside the mesh (or of a row node the walk never reached).
const UNPLACED: ArcPosition = ArcPosition {
    piece: usize::MAX,
    s: f64::NAN,
};

/// The row nodes of a pair in a dense numbering, with the interface edges between them.
struct Interface<'a> {
    /// The slave mesh.
    mesh: &'a Mesh,
    /// Dense index of each mesh node (`usize::MAX` for nodes without a row).
    local: Vec<usize>,
    /// Mesh node of each dense index, in the order of first appearance among the rows.
    members: Vec<usize>,
    /// Interface neighbours of each member (both directions).
    adjacency: Vec<Vec<usize>>,
    /// Boundary successors of each member (body on the left).
    forward: Vec<Vec<usize>>,
    /// 0 when the row nodes' bounding box is at least as wide as tall (order along x), else 1.
    axis: usize,
}

impl<'a> Interface<'a> {
    /// The distinct row nodes among `nodes` and the boundary edges of `mesh` joining two of
    /// them, oriented as the boundary, without repeats; and the axis.
    fn new(mesh: &'a Mesh, nodes: &[usize]) -> Self {
        let n = mesh.nodes.len();
        let mut local = vec![usize::MAX; n];
        let mut members: Vec<usize> = Vec::new();
        for &v in nodes {
            if v < n && local[v] == usize::MAX {
                local[v] = members.len();
                members.push(v);
            }
        }
        let m = members.len();
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
        let mut interface = Self {
            mesh,
            local,
            members,
            adjacency,
            forward,
            axis: 0,
        };
        interface.axis = interface.axis();
        interface
    }

    /// The point of member `i`.
    fn point(&self, i: usize) -> Point {
        self.mesh.nodes[self.members[i]]
    }

    /// 0 (x) when the members' bounding box is at least as wide as it is tall, 1 (y) otherwise.
    fn axis(&self) -> usize {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for i in 0..self.members.len() {
            let p = self.point(i);
            lo = [lo[0].min(p[0]), lo[1].min(p[1])];
            hi = [hi[0].max(p[0]), hi[1].max(p[1])];
        }
        usize::from(hi[1] - lo[1] > hi[0] - lo[0])
    }

    /// The order along the axis: coordinate along it, then the other one, then node index.
    fn before(&self, i: usize, j: usize) -> Ordering {
        let (p, q) = (self.point(i), self.point(j));
        let axis = self.axis;
        p[axis]
            .total_cmp(&q[axis])
            .then(p[1 - axis].total_cmp(&q[1 - axis]))
            .then(self.members[i].cmp(&self.members[j]))
    }

    /// The pieces (connected components), each as its start and its members, in the order of
    /// their starts along the axis.
    fn pieces(&self) -> Vec<(usize, Vec<usize>)> {
        let m = self.members.len();
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
                for &w in &self.adjacency[v] {
                    if component[w] == usize::MAX {
                        component[w] = id;
                        stack.push(w);
                    }
                }
            }
            let start = self.start(seed, &all);
            pieces.push((start, all));
        }
        pieces.sort_by(|a, b| self.before(a.0, b.0));
        pieces
    }

    /// Where a piece starts: its first end along the axis (a chain), or its first node (a loop).
    fn start(&self, seed: usize, all: &[usize]) -> usize {
        let ends: Vec<usize> = all
            .iter()
            .copied()
            .filter(|&v| self.adjacency[v].len() <= 1)
            .collect();
        let pool = if ends.is_empty() { all } else { &ends };
        pool.iter()
            .copied()
            .min_by(|&i, &j| self.before(i, j))
            .unwrap_or(seed)
    }

    /// The position of every member: each piece walked from its start, `s` growing by the
    /// straight distance between consecutive nodes of the walk, across pieces too.
    fn walk(&self, pieces: &[(usize, Vec<usize>)]) -> Vec<ArcPosition> {
        let m = self.members.len();
        let mut position = vec![UNPLACED; m];
        let mut visited = vec![false; m];
        let mut s = 0.0;
        let mut last: Option<usize> = None;
        for (k, (start, all)) in pieces.iter().enumerate() {
            let mut current = *start;
            let mut remaining = all.len();
            loop {
                if let Some(prev) = last {
                    s += geometry::distance(self.point(prev), self.point(current));
                }
                visited[current] = true;
                position[current] = ArcPosition { piece: k, s };
                last = Some(current);
                remaining -= 1;
                if remaining == 0 {
                    break;
                }
                match self.next(current, all, &visited) {
                    Some(w) => current = w,
                    None => break,
                }
            }
        }
        position
    }

    /// The node after `current`: an unvisited neighbour, the boundary's own successor first (it
    /// decides the direction of a closed loop; a chain end has one neighbour only); when stuck,
    /// the nearest unvisited node of the piece.
    fn next(&self, current: usize, all: &[usize], visited: &[bool]) -> Option<usize> {
        self.forward[current]
            .iter()
            .chain(&self.adjacency[current])
            .copied()
            .find(|&w| !visited[w])
            .or_else(|| {
                let here: Point = self.point(current);
                all.iter()
                    .copied()
                    .filter(|&w| !visited[w])
                    .min_by(|&i, &j| {
                        geometry::distance(here, self.point(i))
                            .total_cmp(&geometry::distance(here, self.point(j)))
                            .then(self.before(i, j))
                    })
            })
    }
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
