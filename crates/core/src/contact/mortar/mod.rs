//! Mortar contact rows: segment-to-segment integration with a dual (biorthogonal) slave basis
//! (Wohlmuth 2000; Popp, Gee & Wall 2009/2010; Puso & Laursen 2004).
//!
//! # Rows
//!
//! The slave **interface segments** are the slave boundary edges with both ends candidates
//! that some candidate master segment *faces* (outward normals at an angle whose cosine is
//! below −[`FACING`], as in node-to-segment) and *covers* (its orthogonal
//! projection onto the edge overlaps it, the edge not lying behind it by more than the overlap
//! limit).  The slave nodes are their nodes.  Each slave node j gets the **averaged normal**
//! n_j: the normalised sum of the outward unit normals of the interface segments that touch it
//! — only those: at a body corner whose other edge does not face the master (a block's corner at
//! the end of a flat contact zone) n_j is the facing edge's own normal; at a corner where both
//! edges face the master (a wedge tip) it is their bisector; at the last node of the zone it is
//! its one segment's normal.  Along a slave segment the normal is interpolated linearly,
//! n(ξ) = (1 − ξ) n₁ + ξ n₂.  This field only pairs slave points with master points (the
//! projection below); frictionless rows act along the master's normals (see "Why the master's
//! normal"), frictional ones along the interface's (see "Frictional pairs").
//!
//! For each interface segment the master segments near it (an R-tree query, O(log m)) are
//! projected onto it along that field: each master end y gives the ξ with
//! (x(ξ) − y) × n(ξ) = 0, a quadratic (linear when n₁ ∥ n₂).  The image [ξ_a, ξ_b] is clipped
//! to [0, 1], and each clipped piece is integrated by a 3-point Gauss rule: at each point the
//! slave point x(ξ) is projected along n̂(ξ) onto the master segment (parameter η: the master
//! point it is paired with), and its gap is its distance from the master segment's line,
//! g = (x(ξ) − y_a)·n_m, n_m the master segment's outward unit normal.  With the dual basis
//! ψ₁ = 2N₁ − N₂, ψ₂ = 2N₂ − N₁ (∫ψ_i N_j = δ_ij ∫N_j on a whole segment, ψ₁ + ψ₂ = 1):
//!
//! ```text
//! M_jk = Σ ∫ ψ_j N_k^master,   D_jj = Σ_k M_jk = ∫_covered ψ_j,   g̃_j = Σ ∫ ψ_j g,
//! ν_j = Σ ∫ ψ_j n_m,   n̄_j = ν_j / |ν_j|,
//! ```
//!
//! summed over the covered parts of slave node j's segments.  On a fully covered segment
//! ∫ψ_j = ∫N_j, so D_jj is the slave's lumped mass ∫N_j.  Slave node j's row is the mortar
//! condition n̄_jᵀ(D_jj u_j − Σₖ M_jk u_k) ≤ g̃_j divided by D_jj:
//!
//! ```text
//! masters = [(k, M_jk / D_jj)],  normal = n̄_j,  gap = g̃_j / D_jj,  tributary = D_jj,
//! ```
//!
//! so its multiplier λ_j is a nodal force like node-to-segment's, λ_j / D_jj the contact
//! pressure, and the weights sum to one (to round-off): a rigid translation of both bodies
//! leaves every row satisfied unchanged.  With a uniform pressure p the slave nodes receive
//! p ∫N_j and the master nodes Σ_j p M_jk = p ∫N_k^master (Σ_j ψ_j = 1): both sides get the
//! consistent nodal forces of p, which is why the contact patch test passes on non-matching
//! meshes.  On conforming meshes every master image is a whole slave segment, M_jk = D_jj δ_jk,
//! and the rows are node-to-segment's (weight 1 on the coincident master node, round-off on its
//! neighbours; the normal the mean of the master normals beside the node).
//!
//! # Why the master's normal
//!
//! The rows are the linearisation of the non-penetration condition about the reference
//! configuration (one QP, small displacements).  The distance of a slave point from a master
//! segment's line changes, to first order, by n_m·(u_master − u_slave) — and by nothing else:
//! moving the slave point along the master segment changes which master point faces it (η), not
//! the distance.  Measured along the slave's own normal n̂ instead, the distance is
//! g / (−n_m·n̂), whose first variation is n_m·Δu / (−n_m·n̂): the same direction n_m, scaled.
//! Rows along the slave's averaged normals (the earlier discretisation) dropped the change of η
//! and so counted a sideways motion of the slave, sin θ per unit, as approach, θ the angle
//! between the two sides' normals: on a curved slave over a flat master the row of a node at
//! angle θ read a slave sliding sideways by s as having moved s sin θ closer.  That is an error
//! of the order of the tangential displacement times θ, first order in the load, and on the
//! Hertz cylinder with a stiff block (E ratio 1000) it made the curved-slave half-width 0.7 %
//! and its profile 1.3 % rms off (node-to-segment, along the master's normals: 0.04 %, 0.2 %;
//! docs/scene.md and BENCHMARKS.md have the figures).  Along n_m a flat master's rows are exactly
//! the vertical condition, and the multipliers sum to the resultant exactly.  On a curved master
//! (a flat slave under a cylinder) the rows act along the cylinder's normals: the pressure is
//! then reported at the slave's (the flat body's) points, which face the cylinder's points
//! displaced sideways by the cylinder's tangential displacement — a physical, not a discrete,
//! difference of position between the two sides' profiles (Hertz's theory neglects it).
//!
//! # Frictional pairs: the interface's normal
//!
//! Frictional pairs ([`Frame::Interface`]) act along the deformed interface instead, normal and
//! tangential rows in one frame.  In half-space theory each surface gives wᵢ = Cᵢ I(p) under the
//! contact pressure (Cᵢ = 1/E′ᵢ the surface compliance, (1 − νᵢ²)/Eᵢ in plane strain and
//! 1/Eᵢ in plane stress, I the same integral of p for both), and over the contact w₁ + w₂ = δ − h₁ − h₂ (hᵢ each surface's height from the contact
//! line), so the deformed interface's height is s = h₁ + w₁ with slope
//! s′ = (C₂ h₁′ − C₁ h₂′)/(C₁ + C₂): each body's surface weighted by the *other* body's
//! compliance, the interface following the stiffer body.  Its normal at slave node j is estimated
//! as n̄_j = unit(C_s n_m − C_m n_j), n_m = unit(∫ψ_j n_m) the master's normal (pointing to the
//! slave) and n_j the slave's outward averaged normal: the plain mean of the two sides' normals
//! for equal materials (exact on two mirror-image cylinders, whose interface is flat; half the
//! cylinder's tilt on a flat block under it), the stiffer side's normal when the other is much
//! softer.  Coulomb's cone and the split of the traction into p and q belong to that interface:
//! rows tilted from it by φ report q + p φ (along the slave's normals the mirror cylinders' q was
//! off by p·x/R, odd in x; along the master's the flat block's by as much on the other side).
//! Both rows share the frame because they are the two components of one traction λ n̄ + λₜ t̄
//! (the cone bounds λₜ by the normal force orthogonal to it) and of one relative displacement.
//!
//! The gap is n̄·(x − y) and the tangential reference t̄·(x − y), x − y = −∫ψ_j g n̂ / D_jj the
//! paired points' separation (paired along the slave's normal): the reference is k gₙ with the
//! [pairing slope](super::ContactRow::pairing_slope) k = (t̄·n_j)/(n̄·n_j), so that a node that
//! closes its gap along the pairing direction and sticks lands on its paired point and has not
//! slipped (with rows tilted from the pairing direction and no reference, the closing of the gap
//! read as slip: the Cattaneo stick zone came out 10 % short).
//!
//! The pair's `normal_force` (Σλ) is a sum of magnitudes along each row's normal; the report's
//! `force` is the resultant vector Σ λ n + λₜ t, equal to the slave's contact force.
//!
//! # Ends of the contact zone
//!
//! Only the covered part of a slave segment is integrated: a segment the master covers only
//! partly (the slave reaches past the master's end) contributes ∫_covered ψ_j, and D_jj stays
//! Σ_k M_jk so the weights still sum exactly to one.  The dual function is negative near the
//! other node (ψ_j < 0 where N_j < ⅓), so a node whose segments are covered only near their far
//! ends gets a small or negative D_jj and huge weights M_jk / D_jj.  Such a node gets **no row**:
//! a slave node gets a row only when D_jj ≥ [`MIN_SHARE`] × (its full share Σ |e|/2 of the
//! interface segments e that touch it).  With one segment covered over a fraction c from its far
//! end, D_jj / (|e|/2) = 3c² − 2c, so the row needs c ≥ 0.77; below that the node is left to its
//! neighbour, whose row integrates the covered part.  Every slave candidate without a row —
//! below the share, on no interface segment, or facing nothing — is counted in
//! [`PairRows::unmatched`](super::PairRows::unmatched) (and so reported), never silently
//! dropped.  A slave node that starts inside the master and gets no row refuses the scene, as
//! with node-to-segment.
//!
//! # Quadrature
//!
//! On a straight slave segment with parallel nodal normals (every flat stretch of an interface)
//! η(ξ) and g(ξ) are affine, so ψ_j N_k and ψ_j g are quadratics: the 3-point rule (exact to
//! degree 5) integrates them exactly.  Where the normals differ (a curved, polygonal slave
//! side, the two nodal normals at an angle Δθ) η(ξ) is a ratio of linear functions whose
//! expansion in ξ has coefficients O(Δθ^k) at degree k, so the rule misses O(Δθ⁵) relative
//! (tested below 10⁻² Δθ⁵; measured 10⁻⁷ at Δθ = 0.3 and 10⁻¹⁰ at Δθ = 0.1 for the weighted
//! gap along the slave normal), far below the discretisation error.  The gap integrated now, the
//! distance from the master segment's line, is affine in ξ on every piece, so ψ_j g is
//! integrated exactly; the M_jk keep the O(Δθ⁵) above.
//!
//! # Limits
//!
//! The master surface must be single-valued along the slave normals within the search radius
//! (no folds): two master segments whose images overlap on the same slave segment both
//! contribute.  Master segments are searched within the distance of the nearest one plus the
//! pair's overlap limit plus half the slave segment.
//!
//! # Cost
//!
//! One R-tree query per slave segment (radius: half the segment plus the distance of the
//! nearest master segment plus the overlap limit) and a few master segments each: O(m log m)
//! like the indexed node-to-segment search.  A slave segment far from the master (a far side
//! inside a large region box) queries O(distance / h) segments, each rejected by the facing
//! test.  Measured with `signorini check` on `sh scripts/strip-scene.sh --length L
//! --foundation-layers 4` (best of three alternating runs of each formulation, shared 2-core
//! machine at load 4–6; `contact_rows` alone timed in-process, best of three):
//!
//! | scene | rows | check, node-to-segment | check, mortar | ratio | `contact_rows` ratio |
//! |---|---|---|---|---|---|
//! | L = 100 | 10 001 | 1.01 s | 0.99 s | 0.98 | 0.94 (0.164 s → 0.155 s) |
//! | L = 400 | 40 001 | 6.42 s | 6.15 s | 0.96 | 1.01 (0.478 s → 0.482 s) |
//! | L = 100, foundation hmax 0.0071 (non-matching) | 14 086 | 1.35–1.77 s | 1.77–1.78 s | ≈ 1 | — |
//! | L = 100, region = [0, 100, 0.96, 1.02] | 10 001 | 1.21 s | 1.13 s | 0.93 | — |
//!
//! Most of the time of `contact_rows` is the shared work (overlap depths, candidate masks):
//! building mortar rows costs about what the node-to-segment search does.

mod geometry;
#[cfg(test)]
mod tests;

use super::search::SegmentIndex;
use super::{Built, ContactRow, FACING};
use crate::geometry::tangent;
use crate::geometry::Point;
use crate::mesh::Mesh;
use geometry::{dot, dual, edge_normal, nodal_normals, sub, unit, SlaveSegment};

/// The smallest D_jj, as a share of the slave node's full share ∫N_j of its interface segments,
/// that gets a row (see the module docs): at 1/4 the weights M_jk / D_jj stay below about 16 in
/// magnitude, while a node whose segments are covered over three quarters or more keeps its row.
pub(super) const MIN_SHARE: f64 = 0.25;

/// How far, as a fraction of its length, a slave edge whose ends start outside the master may
/// lie behind a master segment that covers it: the sagitta of a polygonal curved interface,
/// L·θ/8 for a turn of θ between neighbouring edges, is 0.05 L at θ = 0.4 rad (23°).  Deeper
/// means the master segment is on the far side of the master body.
const BEHIND: f64 = 0.05;

/// One slave node's integrals: M_jk (merged by master node), g̃_j, ∫ψ_j n_m (the master-frame
/// row's direction before normalisation) and ∫ψ_j (x − y) (the paired points' separation, which
/// the [`Frame::Interface`] rows split along their own normal and tangent).
#[derive(Debug, Clone, Default)]
struct Sums {
    masters: Vec<(usize, f64)>,
    gap: f64,
    /// ∫ψ_j (x − y), y the master point paired with the slave point x (along the slave normal).
    apart: Point,
    normal: Point,
}

/// Which frame a pair's mortar rows act in (see "Why the master's normal" and "Frictional
/// pairs: the interface's normal").
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Frame {
    /// The master's normals, the gap measured from the master segment's line: frictionless
    /// pairs.
    Master,
    /// Normal and tangential rows along the deformed interface's normal, estimated at each slave
    /// node as the compliance-weighted mean n̄ = (C_s n_m − C_m n_j) / |…| of the master's
    /// normal n_m and the slave's outward normal n_j (each side's normal weighted by the *other*
    /// side's surface compliance C = 1/E′, (1 − ν²)/E in plane strain, 1/E in plane stress: the
    /// interface follows the stiffer body),
    /// the gap n̄·(x − y) of the paired points: frictional pairs.
    Interface {
        /// The slave body's compliance C_s.
        slave: f64,
        /// The master body's compliance C_m.
        master: f64,
    },
}

impl Sums {
    fn add(&mut self, k: usize, m: f64) {
        match self.masters.iter_mut().find(|(n, _)| *n == k) {
            Some((_, v)) => *v += m,
            None => self.masters.push((k, m)),
        }
    }
}

/// The mortar rows of one pair: one row per slave node that the master covers enough (see the
/// module docs).  `inside_s` (the slave nodes on or inside the master) decides how far behind a
/// master segment a slave edge may lie and still be covered by it: up to the overlap `limit`
/// when an end of the edge starts on or inside the master (an initial overlap, negative gaps),
/// otherwise only by [`BEHIND`] × the edge's length plus `tol` — the sagitta of a polygonal
/// curved interface — so that a master segment on the far side of the master body (facing the
/// slave's back across the body) never covers a slave edge.  `frame` chooses the rows' normals.
#[allow(clippy::too_many_arguments)]
pub(super) fn pair_rows(
    slave: &Mesh,
    master: &Mesh,
    cand_s: &[bool],
    master_segments: &[[usize; 2]],
    inside_s: &[Option<f64>],
    tol: f64,
    limit: f64,
    frame: Frame,
) -> Built {
    let mut built = Built {
        rows: Vec::new(),
        unmatched: 0,
        tributary_fallbacks: 0,
        unit_tributaries: 0,
    };
    let segments: Vec<[usize; 2]> = master_segments
        .iter()
        .copied()
        .filter(|&[a, b]| edge_normal(master.nodes[a], master.nodes[b]).is_some())
        .collect();
    let index = SegmentIndex::new(&master.nodes, &segments);
    // Candidate slave edges with the master segments that face them nearby.
    let mut edges: Vec<([usize; 2], Vec<usize>, f64)> = Vec::new();
    for &[p, q] in &slave.boundary {
        if !(cand_s[p] && cand_s[q]) || index.is_empty() {
            continue;
        }
        let (xp, xq) = (slave.nodes[p], slave.nodes[q]);
        let Some(ne) = edge_normal(xp, xq) else {
            continue;
        };
        let own = SlaveSegment {
            x1: xp,
            x2: xq,
            n1: ne,
            n2: ne,
        };
        let behind = if inside_s[p].is_some() || inside_s[q].is_some() {
            limit
        } else {
            (tol + BEHIND * own.length()).min(limit)
        };
        let mid = own.point(0.5);
        let nearest = index.nearest(mid).next().map_or(0.0, |(_, d)| d);
        let radius = 0.5 * own.length() + nearest + behind;
        let mut near: Vec<usize> = index
            .within(mid, radius)
            .filter(|&s| {
                let [a, b] = segments[s];
                let (ya, yb) = (master.nodes[a], master.nodes[b]);
                edge_normal(ya, yb).is_some_and(|nm| dot(nm, ne) <= -FACING)
                    && covers(&own, ya, yb, behind)
            })
            .collect();
        if near.is_empty() {
            continue;
        }
        near.sort_unstable();
        edges.push(([p, q], near, behind));
    }
    let interface: Vec<[usize; 2]> = edges.iter().map(|e| e.0).collect();
    let normals = nodal_normals(&slave.nodes, &interface);
    let mut sums = vec![Sums::default(); slave.nodes.len()];
    let mut share = vec![0.0; slave.nodes.len()];
    for ([p, q], near, behind) in &edges {
        let (Some(n1), Some(n2)) = (normals[*p], normals[*q]) else {
            continue;
        };
        let seg = SlaveSegment {
            x1: slave.nodes[*p],
            x2: slave.nodes[*q],
            n1,
            n2,
        };
        let half = 0.5 * seg.length();
        share[*p] += half;
        share[*q] += half;
        for &s in near {
            let [a, b] = segments[s];
            let (ya, yb) = (master.nodes[a], master.nodes[b]);
            let Some(piece) = seg.clip(ya, yb) else {
                continue;
            };
            let Some(points) = seg.gauss_points(piece, ya, yb) else {
                continue;
            };
            if points.iter().any(|g| g.gap < -behind) {
                // Behind the master segment by more than any accepted overlap: its image runs
                // through the master body (onto its far side).
                continue;
            }
            // The master segment's outward normal (it faces the slave: checked when `near`
            // was built) and, at each point, the slave point's distance from its line.
            let Some(nm) = edge_normal(ya, yb) else {
                continue;
            };
            for g in points {
                let psi = dual(g.xi);
                let n = unit(seg.normal(g.xi)).unwrap_or(seg.n1);
                let gap = dot(sub(seg.point(g.xi), ya), nm);
                for (node, psi) in [(*p, psi[0]), (*q, psi[1])] {
                    let w = psi * g.weight;
                    let s = &mut sums[node];
                    s.add(a, w * (1.0 - g.eta));
                    s.add(b, w * g.eta);
                    s.gap += w * gap;
                    // y = x + g n̂: x − y = −g n̂.
                    s.apart = [s.apart[0] - w * g.gap * n[0], s.apart[1] - w * g.gap * n[1]];
                    s.normal = [s.normal[0] + w * nm[0], s.normal[1] + w * nm[1]];
                }
            }
        }
    }
    for (j, x) in slave.nodes.iter().enumerate() {
        if !cand_s[j] {
            continue;
        }
        let (Some(n), s) = (normals[j], &sums[j]) else {
            built.unmatched += 1;
            continue;
        };
        let d: f64 = s.masters.iter().map(|m| m.1).sum();
        if !(d >= MIN_SHARE * share[j] && d > 0.0) {
            built.unmatched += 1;
            continue;
        }
        let master_normal = unit(s.normal).unwrap_or([-n[0], -n[1]]);
        let (normal, gap, pairing_slope) = match frame {
            Frame::Master => (master_normal, s.gap / d, 0.0),
            Frame::Interface { slave, master } => {
                let mean = [
                    slave * master_normal[0] - master * n[0],
                    slave * master_normal[1] - master * n[1],
                ];
                let normal = unit(mean).unwrap_or(master_normal);
                let t = tangent(normal);
                // The pairing direction is the slave's normal: (t·n_j)/(n̄·n_j), n̄·n_j < 0
                // since n̄ lies between n_m and −n_j, which face each other.
                let slope = dot(t, n) / dot(normal, n);
                (normal, dot(normal, s.apart) / d, slope)
            }
        };
        built.rows.push(ContactRow {
            slave_node: j,
            masters: s.masters.iter().map(|&(k, m)| (k, m / d)).collect(),
            normal,
            gap: if gap.abs() <= tol { 0.0 } else { gap },
            tributary: d,
            position: *x,
            pairing_slope,
        });
    }
    built
}

/// True when master segment `ya`–`yb` covers part of the slave segment `own` (whose normals
/// are its own edge normal) along its normal, the slave not lying behind it by more than
/// `limit` at the middle of the covered part.
fn covers(
    own: &SlaveSegment,
    ya: crate::geometry::Point,
    yb: crate::geometry::Point,
    limit: f64,
) -> bool {
    let Some(piece) = own.clip(ya, yb) else {
        return false;
    };
    let x = own.point(0.5 * (piece.lo + piece.hi));
    let Some(nm) = edge_normal(ya, yb) else {
        return false;
    };
    // Gap along the master normal (the segments face each other): (x − ya)·n_m.
    dot(sub(x, ya), nm) >= -limit
}
