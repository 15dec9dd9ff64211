//! The property "a `solved` answer leaves no slave inside its master", judged per contact pair
//! against that pair's own motion, from the output fields (the displacement written to
//! solution.vtu) and the model's rows and meshes — independently of the residuals and of the
//! scale the core judges them with.
//!
//! **Allowed penetration** of pair P: `t = max(1e-6 · U, 1e-12 · L)`, where
//! * U = max |u| over the nodes of P's two bodies (the pair's own motion: a body that cannot
//!   push on P does not loosen its check);
//! * L = the largest |coordinate| of P's two bodies' nodes, fixed data of the scene: the gaps are
//!   differences of coordinates, rounded to ~1e-16 L, so a pair that does not move is held to
//!   10⁴ times that round-off, not to zero.
//!
//! **Measured**, for each slave node X of P:
//! 1. its rows, exactly as the model states them (`ContactRow`: −n·u_X + Σₖ wₖ n·u_k ≤ g, node-
//!    to-segment and mortar alike): a row violated by more than t;
//! 2. the deformed geometry: X + u_X inside the master's deformed boundary, deeper (distance to
//!    the nearest deformed master edge) than t plus what the model itself leaves there —
//!    node-to-segment: the linearisation of its own row (the row measures the depth along the
//!    initial normal at the initial projection point; the deformed segment has turned and the node
//!    has slipped along it, so the distance to that deformed segment may exceed the row's depth
//!    by a term of order |u|²/h, which is the small-displacement model's, not the solver's);
//!    mortar: half the pair's motion (a row holds a dual-basis-weighted mean of the gaps over the
//!    node's support, so the node itself may dip by a fraction of the motion while every row
//!    holds); a slave node with no row: nothing beyond t.
//!
//!    The geometry is only judged where the linear model holds: U at most 10 % of the smaller
//!    body's size (beyond, bodies may sweep through each other in the deformed picture without
//!    any error of the solver); the rows are judged always.

use signorini::run::Outcome;
use signorini_core::contact::{ContactRow, PairRows};
use signorini_core::geometry::project_on_segment;
use signorini_core::scene::{Formulation, Scene};

type Point = [f64; 2];

/// Node `n` of body `b`, displaced.
fn deformed(outcome: &Outcome, b: usize, n: usize) -> Point {
    let x = outcome.model.meshes[b].nodes[n];
    let u = outcome.fields[b].displacement[n];
    [x[0] + u[0], x[1] + u[1]]
}

/// U and L of the module's formula for the bodies `bodies`.
fn motion_and_extent(outcome: &Outcome, bodies: [usize; 2]) -> (f64, f64) {
    let mut motion = 0.0_f64;
    let mut extent = 0.0_f64;
    for b in bodies {
        for (x, u) in outcome.model.meshes[b]
            .nodes
            .iter()
            .zip(&outcome.fields[b].displacement)
        {
            motion = motion.max(u[0].hypot(u[1]));
            extent = extent.max(x[0].abs()).max(x[1].abs());
        }
    }
    (motion, extent)
}

/// How far row `r` of `pair` is violated: (−n·u_X + Σₖ wₖ n·u_k) − g (≤ 0 when it holds).
fn row_violation(outcome: &Outcome, pair: &PairRows, r: &ContactRow) -> f64 {
    let n = r.normal;
    let dot = |u: [f64; 2]| n[0] * u[0] + n[1] * u[1];
    let slave = dot(outcome.fields[pair.slave].displacement[r.slave_node]);
    let masters: f64 = r
        .masters
        .iter()
        .map(|&(k, w)| w * dot(outcome.fields[pair.master].displacement[k]))
        .sum();
    -slave + masters - r.gap
}

/// The deformed boundary edges of body `b`.
fn deformed_edges(outcome: &Outcome, b: usize) -> Vec<(Point, Point)> {
    outcome.model.meshes[b]
        .boundary
        .iter()
        .map(|&[a, c]| (deformed(outcome, b, a), deformed(outcome, b, c)))
        .collect()
}

/// Ray casting: is `p` inside the closed curve made of `edges`?
fn inside(p: Point, edges: &[(Point, Point)]) -> bool {
    let mut crossings = 0;
    for (a, b) in edges {
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if x > p[0] {
                crossings += 1;
            }
        }
    }
    crossings % 2 == 1
}

fn distance_to_edges(p: Point, edges: &[(Point, Point)]) -> f64 {
    edges
        .iter()
        .map(|(a, b)| project_on_segment(p, *a, *b).1)
        .fold(f64::INFINITY, f64::min)
}

/// What the model leaves at a slave node beyond the allowance (see the module's item 2), given
/// the node's deformed position `p` and its row, if any.
fn model_share(
    outcome: &Outcome,
    pair: &PairRows,
    row: Option<&ContactRow>,
    p: Point,
    motion: f64,
) -> f64 {
    let Some(r) = row else { return 0.0 };
    match pair.formulation {
        Formulation::Mortar => 0.5 * motion,
        Formulation::NodeToSegment => {
            let [(a, _), (b, _)] = match r.masters.as_slice() {
                [a, b] => [*a, *b],
                _ => return 0.0,
            };
            let (a, b) = (
                deformed(outcome, pair.master, a),
                deformed(outcome, pair.master, b),
            );
            let to_segment = project_on_segment(p, a, b).1;
            (to_segment - row_violation(outcome, pair, r).max(0.0)).max(0.0)
        }
    }
}

/// The smaller side of the bounding boxes of `bodies`.
fn smaller_size(scene: &Scene, bodies: [usize; 2]) -> f64 {
    bodies
        .iter()
        .map(|&b| {
            let bb = signorini_core::geometry::bounding_box(scene.bodies[b].polygon.iter());
            (bb[1] - bb[0]).min(bb[3] - bb[2])
        })
        .fold(f64::INFINITY, f64::min)
}

/// The deepest slave node of `pair` inside the deformed master beyond its allowance, as
/// (depth, allowance, undeformed position).
fn deepest_inside(
    outcome: &Outcome,
    pair: &PairRows,
    allowed: f64,
    motion: f64,
) -> Option<(f64, f64, Point)> {
    let edges = deformed_edges(outcome, pair.master);
    let mesh = &outcome.model.meshes[pair.slave];
    let mut worst: Option<(f64, f64, Point)> = None;
    for &[n, _] in &mesh.boundary {
        let p = deformed(outcome, pair.slave, n);
        if !inside(p, &edges) {
            continue;
        }
        let depth = distance_to_edges(p, &edges);
        let row = pair.rows.iter().find(|r| r.slave_node == n);
        let allowance = allowed + model_share(outcome, pair, row, p, motion);
        if depth > allowance && worst.is_none_or(|w| depth - allowance > w.0 - w.1) {
            worst = Some((depth, allowance, mesh.nodes[n]));
        }
    }
    worst
}

/// The first pair of a `solved` answer whose slave ends inside its master beyond the allowance
/// (the module's formula), described; `None` when every pair keeps out.
pub fn interpenetration(scene: &Scene, outcome: &Outcome) -> Option<String> {
    let finite = outcome
        .fields
        .iter()
        .all(|f| f.displacement.iter().flatten().all(|v| v.is_finite()));
    if !finite {
        return None;
    }
    for pair in &outcome.model.contacts {
        let (motion, extent) = motion_and_extent(outcome, [pair.slave, pair.master]);
        let allowed = (1e-6 * motion).max(1e-12 * extent);
        let name = |b: usize| &scene.bodies[b].name;
        let worst_row = pair
            .rows
            .iter()
            .map(|r| (row_violation(outcome, pair, r), r.position))
            .fold((f64::NEG_INFINITY, [0.0, 0.0]), |w, x| {
                if x.0 > w.0 {
                    x
                } else {
                    w
                }
            });
        if worst_row.0 > allowed {
            return Some(format!(
                "contact #{}: a row of slave {:?} at {:?} violated by {:.3e} = {:.1e} of the \
                 pair's motion {motion:.3e} (allowed {allowed:.1e})",
                pair.pair + 1,
                name(pair.slave),
                worst_row.1,
                worst_row.0,
                worst_row.0 / motion,
            ));
        }
        if motion > 0.1 * smaller_size(scene, [pair.slave, pair.master]) {
            continue;
        }
        if let Some((depth, allowance, at)) = deepest_inside(outcome, pair, allowed, motion) {
            return Some(format!(
                "contact #{}: slave {:?} node at {at:?} ends {depth:.3e} inside master {:?} \
                 = {:.1e} of the pair's motion {motion:.3e} (allowed {allowance:.1e})",
                pair.pair + 1,
                name(pair.slave),
                name(pair.master),
                depth / motion,
            ));
        }
    }
    None
}
