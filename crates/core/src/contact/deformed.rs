//! The deformed-geometry check of an answer: does a slave node end inside its master's deformed
//! boundary by more than the small-displacement model allows?
//!
//! The rows hold the model's linearised condition at the nodes that have one; the check looks at
//! every slave boundary node of a pair, with a row or without (a node outside the region box, one
//! beyond the master's end that the master's corner moves over, one that slid past its segment),
//! against the master's deformed outline.  Its allowance for pair P is
//!
//! ```text
//! t = max(10⁻⁶ U, 10⁻¹² L) + s
//! ```
//!
//! * U = max |u| over the nodes of P's two bodies (the pair's own motion);
//! * L = the largest |coordinate| of those nodes (the gaps are differences of coordinates,
//!   rounded to ~10⁻¹⁶ L: a pair that does not move is held to 10⁴ times that round-off);
//! * s = what the model itself leaves at the node — node-to-segment: how far the node is from its
//!   own deformed segment beyond the row's violation (the row measures the depth along the
//!   initial normal at the initial projection point; the turned and slid segment may be farther
//!   by a term of order |u|²/h); mortar: U / 2 (a row holds a dual-basis-weighted mean of the gaps
//!   over the node's support, so the node itself may dip while every row holds); no row: 0.
//!
//! A pair whose motion U exceeds a tenth of the smaller body's size is not judged: there the
//! bodies may sweep through each other in the deformed picture without any error of the solver,
//! and the small-displacement model is not meant to hold.  Such a pair is still checked: when
//! every slave node keeps out, that is a verdict at any motion and it passes; when one ends inside,
//! the check cannot tell the solver's error from the model's range, so it neither demotes the
//! answer nor passes it silently — [`deformed_check`] lists the pair and its deepest node
//! ([`Unjudged`]), and the run reports it as a warning.

use crate::geometry::{self, Point};
use crate::mesh::Mesh;
use crate::scene::Formulation;

use super::search::SegmentIndex;
use super::{ContactRow, PairRows};

/// Relative allowance on the pair's motion U (the module's formula).
pub const MOTION_FRACTION: f64 = 1e-6;

/// Relative allowance on the pair's coordinates L (the module's formula).
pub const ROUND_OFF_FRACTION: f64 = 1e-12;

/// Pairs that move more than this fraction of the smaller body's size are beyond the
/// small-displacement model: an overlap found there is reported as unjudged, not as a failure.
pub const LARGE_MOTION: f64 = 0.1;

/// A slave node that ends inside its deformed master beyond the allowance.
#[derive(Debug, Clone, PartialEq)]
pub struct DeformedOverlap {
    /// Index of the pair in the scene (0-based).
    pub pair: usize,
    /// Slave body index.
    pub slave: usize,
    /// Master body index.
    pub master: usize,
    /// The node's undeformed position.
    pub position: Point,
    /// Whether the node has a contact row.
    pub has_row: bool,
    /// Distance of the deformed node to the master's deformed boundary (it is inside).
    pub depth: f64,
    /// The allowance t at the node.
    pub allowed: f64,
    /// The pair's motion U.
    pub motion: f64,
}

/// A pair the check could not judge: it moves more than [`LARGE_MOTION`] of its smaller body,
/// and a slave node ends inside its deformed master beyond the allowance.
#[derive(Debug, Clone, PartialEq)]
pub struct Unjudged {
    /// The pair's deepest slave node beyond its allowance (its `pair`, bodies and motion U).
    pub overlap: DeformedOverlap,
    /// The smaller body's size (the smaller side of its bounding box).
    pub size: f64,
}

/// What the deformed-geometry check found over every pair.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DeformedCheck {
    /// The slave node deepest beyond its allowance, over the judged pairs (`None`: every slave
    /// node keeps out).
    pub worst: Option<DeformedOverlap>,
    /// The pairs with an overlap that could not be judged (large motion), in pair order.
    pub unjudged: Vec<Unjudged>,
}

/// The slave node that ends deepest beyond its allowance inside its deformed master, over every
/// pair, or `None` when every slave node keeps out (see the module's formula); pairs it could
/// not judge (large motion with an overlap) are left out ([`deformed_check`] lists them).  `displacement[b][n]` is node `n` of
/// body `b`'s displacement.
pub fn deformed_overlap(
    meshes: &[Mesh],
    pairs: &[PairRows],
    displacement: &[&[Point]],
) -> Option<DeformedOverlap> {
    deformed_check(meshes, pairs, displacement).worst
}

/// [`deformed_overlap`]'s finding and the pairs it could not judge (none when a displacement
/// is not finite: the finite check is another's).
pub fn deformed_check(
    meshes: &[Mesh],
    pairs: &[PairRows],
    displacement: &[&[Point]],
) -> DeformedCheck {
    let all_finite = displacement
        .iter()
        .all(|d| d.iter().flatten().all(|v| v.is_finite()));
    let mut check = DeformedCheck::default();
    if !all_finite {
        return check;
    }
    for pair in pairs {
        let Some(found) = pair_overlap(meshes, pair, displacement) else {
            continue;
        };
        let [motion, _, size] = motion_extent_size(meshes, displacement, [pair.slave, pair.master]);
        if motion > LARGE_MOTION * size {
            check.unjudged.push(Unjudged {
                overlap: found,
                size,
            });
            continue;
        }
        let excess = |o: &DeformedOverlap| o.depth - o.allowed;
        if check
            .worst
            .as_ref()
            .is_none_or(|w| excess(&found) > excess(w))
        {
            check.worst = Some(found);
        }
    }
    check
}

/// The deformed positions of body `b`'s nodes.
fn deformed_nodes(mesh: &Mesh, u: &[Point]) -> Vec<Point> {
    mesh.nodes
        .iter()
        .zip(u)
        .map(|(x, u)| [x[0] + u[0], x[1] + u[1]])
        .collect()
}

/// U, L and the smaller body's size for the bodies `bodies`.
fn motion_extent_size(meshes: &[Mesh], displacement: &[&[Point]], bodies: [usize; 2]) -> [f64; 3] {
    let (mut motion, mut extent, mut size) = (0.0_f64, 0.0_f64, f64::INFINITY);
    for b in bodies {
        for (x, u) in meshes[b].nodes.iter().zip(displacement[b]) {
            motion = motion.max(u[0].hypot(u[1]));
            extent = extent.max(x[0].abs()).max(x[1].abs());
        }
        let bb = geometry::bounding_box(meshes[b].nodes.iter());
        size = size.min((bb[1] - bb[0]).min(bb[3] - bb[2]));
    }
    [motion, extent, size]
}

/// Is `p` inside the closed curve of `edges`?  By its winding number (the signed crossings of
/// the horizontal line through `p` to its right, upward +1, downward −1): non-zero inside a
/// counter-clockwise outline.
fn inside(p: Point, edges: &[(Point, Point)]) -> bool {
    let mut winding = 0_i64;
    for (a, b) in edges {
        // Which side of the line a → b the point is on (> 0: left).
        let side = (b[0] - a[0]) * (p[1] - a[1]) - (p[0] - a[0]) * (b[1] - a[1]);
        if a[1] <= p[1] && b[1] > p[1] && side > 0.0 {
            winding += 1;
        } else if a[1] > p[1] && b[1] <= p[1] && side < 0.0 {
            winding -= 1;
        }
    }
    winding != 0
}

/// How far `row` is violated by the displacement: (−n·u_X + Σₖ wₖ n·u_k) − g.
fn row_violation(row: &ContactRow, u_slave: &[Point], u_master: &[Point]) -> f64 {
    let n = row.normal;
    let dot = |u: Point| n[0] * u[0] + n[1] * u[1];
    let masters: f64 = row.masters.iter().map(|&(k, w)| w * dot(u_master[k])).sum();
    -dot(u_slave[row.slave_node]) + masters - row.gap
}

/// The model's share s of the allowance at a slave node at deformed position `p`.
fn model_share(
    pair: &PairRows,
    row: &ContactRow,
    p: Point,
    master_now: &[Point],
    u: [&[Point]; 2],
    motion: f64,
) -> f64 {
    match pair.formulation {
        Formulation::Mortar => 0.5 * motion,
        Formulation::NodeToSegment => match row.masters.as_slice() {
            [(a, _), (b, _)] => {
                let to_segment = geometry::project_on_segment(p, master_now[*a], master_now[*b]).1;
                (to_segment - row_violation(row, u[0], u[1]).max(0.0)).max(0.0)
            }
            _ => 0.0,
        },
    }
}

/// The deepest slave node of `pair` beyond its allowance, if any (at any motion: the caller
/// weighs [`LARGE_MOTION`]).
fn pair_overlap(
    meshes: &[Mesh],
    pair: &PairRows,
    displacement: &[&[Point]],
) -> Option<DeformedOverlap> {
    let [motion, extent, _] = motion_extent_size(meshes, displacement, [pair.slave, pair.master]);
    let floor = (MOTION_FRACTION * motion).max(ROUND_OFF_FRACTION * extent);
    let (slave, master) = (&meshes[pair.slave], &meshes[pair.master]);
    let u = [displacement[pair.slave], displacement[pair.master]];
    let master_now = deformed_nodes(master, u[1]);
    let slave_now = deformed_nodes(slave, u[0]);
    let edges: Vec<(Point, Point)> = master
        .boundary
        .iter()
        .map(|&[a, b]| (master_now[a], master_now[b]))
        .collect();
    let index = SegmentIndex::new(&master_now, &master.boundary);
    let mut row_of = vec![None; slave.nodes.len()];
    for r in &pair.rows {
        row_of[r.slave_node] = Some(r);
    }
    let mut worst: Option<DeformedOverlap> = None;
    for &[n, _] in &slave.boundary {
        let p = slave_now[n];
        // The nearest deformed master edge first (an R-tree query): a node within the floor of
        // the boundary passes whichever side it is on, and only the others need the ray cast.
        let depth = index.nearest(p).next().map(|(e, _)| {
            let (a, b) = edges[e];
            geometry::project_on_segment(p, a, b).1
        })?;
        if depth <= floor || !inside(p, &edges) {
            continue;
        }
        let row = row_of[n];
        let share = row.map_or(0.0, |r| model_share(pair, r, p, &master_now, u, motion));
        let allowed = floor + share;
        let excess = depth - allowed;
        if excess > 0.0 && worst.as_ref().is_none_or(|w| excess > w.depth - w.allowed) {
            worst = Some(DeformedOverlap {
                pair: pair.pair,
                slave: pair.slave,
                master: pair.master,
                position: slave.nodes[n],
                has_row: row.is_some(),
                depth,
                allowed,
                motion,
            });
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    //! Hand-made boundary loops and displacements whose answer is known by construction of the
    //! geometry (not by the code): a slave square pushed into a fixed master square by a known
    //! depth, rigid motions that keep out, and the two exemptions (the model's share, large
    //! motion).
    #![allow(clippy::unwrap_used, clippy::expect_used)] // tests may unwrap

    use super::*;

    /// Master: the unit square [0, 1]²; slave: the square [0.25, 0.75] × [1, 1.5] on its top,
    /// bottom edge split at x = 0.5 (nodes 0..5, counter-clockwise from (0.25, 1)).
    fn bodies() -> Vec<Mesh> {
        vec![
            Mesh::boundary_loop(vec![
                [0.25, 1.0],
                [0.5, 1.0],
                [0.75, 1.0],
                [0.75, 1.5],
                [0.25, 1.5],
            ]),
            Mesh::boundary_loop(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]),
        ]
    }

    /// The pair (slave 0, master 1) with the given rows.
    fn pair(rows: Vec<ContactRow>, formulation: Formulation) -> PairRows {
        PairRows {
            pair: 0,
            slave: 0,
            master: 1,
            formulation,
            friction: None,
            rows,
            conforming: false,
            candidates: 3,
            unmatched: 0,
            tributary_fallbacks: 0,
            unit_tributaries: 0,
            overlap: None,
        }
    }

    /// A node-to-segment row of slave node `node` on the master's top edge (3 → 2, normal +y).
    fn top_row(node: usize, x: f64) -> ContactRow {
        ContactRow {
            slave_node: node,
            masters: vec![(3, 1.0 - x), (2, x)],
            normal: [0.0, 1.0],
            gap: 0.0,
            tributary: 0.125,
            position: [x, 1.0],
            pairing_slope: 0.0,
        }
    }

    fn check(pair: &PairRows, u: &[Vec<Point>]) -> Option<DeformedOverlap> {
        let meshes = bodies();
        let u: Vec<&[Point]> = u.iter().map(Vec::as_slice).collect();
        deformed_overlap(&meshes, std::slice::from_ref(pair), &u)
    }

    #[test]
    fn a_slave_without_rows_pushed_in_is_found_at_its_depth() {
        // The slave moves down by d = 0.01 everywhere, the master stays: its three bottom
        // nodes end d inside the master, 1.0 of the pair's motion.
        let d = 0.01;
        let u = vec![vec![[0.0, -d]; 5], vec![[0.0, 0.0]; 4]];
        let found = check(&pair(Vec::new(), Formulation::NodeToSegment), &u).unwrap();
        assert!((found.depth - d).abs() < 1e-15, "{found:?}");
        assert_eq!(found.motion, d);
        assert!(!found.has_row);
        assert_eq!(found.position[1], 1.0);
    }

    #[test]
    fn a_rigid_motion_of_both_bodies_keeps_out() {
        let u = vec![vec![[0.02, -0.01]; 5], vec![[0.02, -0.01]; 4]];
        assert_eq!(
            check(&pair(Vec::new(), Formulation::NodeToSegment), &u),
            None
        );
    }

    #[test]
    fn a_dip_within_the_floor_passes_and_one_just_beyond_does_not() {
        // Master moves up by U = 0.01 (its top nodes 2, 3), the slave's middle node dips into
        // it by 0.5e-6 U (passes: within 1e-6 U) or 2e-6 U (fails).
        let motion = 0.01;
        let mut u = vec![vec![[0.0, motion]; 5], vec![[0.0, 0.0]; 4]];
        u[1][2] = [0.0, motion];
        u[1][3] = [0.0, motion];
        u[0][1] = [0.0, motion - 0.5e-6 * motion];
        assert_eq!(
            check(&pair(Vec::new(), Formulation::NodeToSegment), &u),
            None
        );
        u[0][1] = [0.0, motion - 2e-6 * motion];
        let found = check(&pair(Vec::new(), Formulation::NodeToSegment), &u).unwrap();
        assert!((found.depth - 2e-6 * motion).abs() < 1e-12 * motion);
    }

    #[test]
    fn mortar_rows_may_dip_by_half_the_motion_and_no_more() {
        // Master fixed, the slave's middle node (with a mortar row) moves down 0.4 U or 0.6 U,
        // U = 0.01 its motion: within U/2 + 1e-6 U, then beyond.
        let motion = 0.01;
        let mut row = top_row(1, 0.5);
        row.masters = vec![(3, 0.5), (2, 0.5)];
        let mortar = pair(vec![row], Formulation::Mortar);
        let mut u = vec![vec![[0.0, 0.0]; 5], vec![[0.0, 0.0]; 4]];
        u[0][3] = [0.0, motion]; // sets U without entering the master
        u[0][1] = [0.0, -0.4 * motion];
        assert_eq!(check(&mortar, &u), None);
        u[0][1] = [0.0, -0.6 * motion];
        let found = check(&mortar, &u).unwrap();
        assert!(found.has_row);
        assert!((found.allowed - (0.5 + 1e-6) * motion).abs() < 1e-15);
    }

    #[test]
    fn a_node_to_segment_row_measures_its_own_segment_and_not_more() {
        // The master's top edge tilts: node 3 (0, 1) rises by 0.02, node 2 (1, 1) stays.  The
        // slave's bottom nodes at x = 0.25, 0.5, 0.75, each with a row on that edge, stay put:
        // the deformed edge passes (1 − x) · 0.02 above each; its row, −n·u_X + Σ w n·u_k ≤ 0
        // with n = +y, reads (1 − x) · 0.02 > 0: violated by that, so the model's share is
        // distance − violation ≤ 0 and each node is judged at the floor: the deepest, x = 0.25
        // (0.015 inside), is found.
        let mut u = vec![vec![[0.0, 0.0]; 5], vec![[0.0, 0.0]; 4]];
        u[1][3] = [0.0, 0.02];
        let rows = vec![top_row(0, 0.25), top_row(1, 0.5), top_row(2, 0.75)];
        let found = check(&pair(rows, Formulation::NodeToSegment), &u).unwrap();
        assert!(found.has_row);
        assert_eq!(found.position, [0.25, 1.0]);
        // Distance to the tilted edge: 0.015 · cos(atan 0.02).
        let depth = 0.015 / (1.0_f64 + 0.02 * 0.02).sqrt();
        assert!((found.depth - depth).abs() < 1e-12, "{found:?}");

        // The rows hold (each node rises with its projection point) but the nodes have slid
        // 0.04 to the left, up the tilted edge: each ends 0.04 · 0.02 = 8e-4 below the edge
        // above it, which is the linearisation's, not the solver's (the row measures along the
        // old normal at the old point): within the share, not found.  (U ≈ 0.043 < 0.05.)
        let mut u = vec![vec![[0.0, 0.0]; 5], vec![[0.0, 0.0]; 4]];
        u[1][3] = [0.0, 0.02];
        for (node, x) in [(0, 0.25), (1, 0.5), (2, 0.75)] {
            u[0][node] = [-0.04, (1.0 - x) * 0.02];
        }
        let rows = vec![top_row(0, 0.25), top_row(1, 0.5), top_row(2, 0.75)];
        assert_eq!(
            check(&pair(rows.clone(), Formulation::NodeToSegment), &u),
            None
        );
        // Without their rows the same nodes are found: the share is the rows'.
        let found = check(&pair(Vec::new(), Formulation::NodeToSegment), &u).unwrap();
        assert!(!found.has_row && found.depth > 7e-4, "{found:?}");
    }

    #[test]
    fn a_pair_moving_more_than_a_tenth_of_its_smaller_body_is_unjudged_and_says_so() {
        // The slave (size 0.5) moves 0.06 > 0.05 into the master: beyond the model's range, so
        // not a failure, but listed as unjudged with its node, depth, motion and size.
        let meshes = bodies();
        let pairs = [pair(Vec::new(), Formulation::NodeToSegment)];
        let u = [vec![[0.0, -0.06]; 5], vec![[0.0, 0.0]; 4]];
        let u: Vec<&[Point]> = u.iter().map(Vec::as_slice).collect();
        let found = deformed_check(&meshes, &pairs, &u);
        assert_eq!(found.worst, None);
        assert_eq!(found.unjudged.len(), 1);
        let unjudged = &found.unjudged[0];
        assert_eq!(unjudged.size, 0.5);
        assert_eq!(unjudged.overlap.motion, 0.06);
        assert!(
            (unjudged.overlap.depth - 0.06).abs() < 1e-15,
            "{unjudged:?}"
        );
        assert_eq!(unjudged.overlap.position[1], 1.0);
        // 0.04 < 0.05: judged (and found), nothing unjudged.
        let u = [vec![[0.0, -0.04]; 5], vec![[0.0, 0.0]; 4]];
        let u: Vec<&[Point]> = u.iter().map(Vec::as_slice).collect();
        let found = deformed_check(&meshes, &pairs, &u);
        assert!(found.worst.is_some());
        assert!(found.unjudged.is_empty());
    }

    #[test]
    fn a_large_motion_that_keeps_out_is_judged_and_passes() {
        // Both bodies translate by 2 (4× the slave's size) and the slave also lifts off by 0.3:
        // beyond a tenth of the body, yet no node ends inside — a verdict at any motion.
        let meshes = bodies();
        let pairs = [pair(Vec::new(), Formulation::NodeToSegment)];
        let u = [vec![[2.0, 2.3]; 5], vec![[2.0, 2.0]; 4]];
        let u: Vec<&[Point]> = u.iter().map(Vec::as_slice).collect();
        assert_eq!(
            deformed_check(&meshes, &pairs, &u),
            DeformedCheck::default()
        );
    }

    #[test]
    fn a_non_finite_answer_is_left_to_the_finite_check() {
        let u = vec![vec![[f64::NAN, -0.01]; 5], vec![[0.0, 0.0]; 4]];
        assert_eq!(
            check(&pair(Vec::new(), Formulation::NodeToSegment), &u),
            None
        );
    }
}
