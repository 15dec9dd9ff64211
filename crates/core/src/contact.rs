//! Node-to-segment contact constraints.
//!
//! For each contact pair, candidate boundary nodes are those in the pair's region box (or, with no
//! box, within one element size of the other body).  The side with more candidates is the slave
//! (unless the scene names it).  Each slave node X is projected onto the closest master segment
//! A–B, X ≈ Y = (1 − t) A + t B, and gives one row
//!
//! ```text
//! −n·u_X + α n·u_A + (1 − α) n·u_B ≤ g,   α = 1 − t,   g = (X − Y)·n,
//! ```
//!
//! with n the master's outward unit normal: the slave may not cross the master segment.  The row's
//! multiplier λ ≥ 0 is the normal contact force at X (force per unit thickness); dividing by the
//! slave node's tributary length gives the contact pressure.  Coincident interface nodes
//! (conforming meshes) give t ∈ {0, 1}: one row per coincident pair.

use crate::geometry::{self, Point};
use crate::mesh::Mesh;
use crate::scene::Scene;

/// One constraint row.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactRow {
    /// Slave node (body-local index).
    pub slave_node: usize,
    /// The master segment's end nodes `[A, B]` (body-local indices).
    pub master_nodes: [usize; 2],
    /// Weight α of A (B gets 1 − α).
    pub alpha: f64,
    /// Master outward unit normal n.
    pub normal: Point,
    /// Initial normal gap g = (X − Y)·n.
    pub gap: f64,
    /// Slave node's tributary length on the interface (for pressure = λ / length).
    pub tributary: f64,
    /// Slave node position X.
    pub position: Point,
}

/// The rows of one contact pair.
#[derive(Debug, Clone, PartialEq)]
pub struct PairRows {
    /// Index of the pair in the scene.
    pub pair: usize,
    /// Slave body index.
    pub slave: usize,
    /// Master body index.
    pub master: usize,
    /// Constraint rows, ordered by slave node.
    pub rows: Vec<ContactRow>,
    /// True when every slave node on the interface (zero initial gap) coincides with a master node.
    pub conforming: bool,
}

/// Why contact rows could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ContactError {
    /// A region box holds no boundary node of a body.
    #[error("contact #{pair}: region {region:?} holds no boundary node of body \"{body}\"")]
    EmptyRegion {
        /// 1-based pair index.
        pair: usize,
        /// The region.
        region: [f64; 4],
        /// Body name.
        body: String,
    },
}

/// Boundary edge lists per node: for each node, the boundary edges (as indices) that touch it.
fn edges_at_nodes(mesh: &Mesh) -> Vec<Vec<usize>> {
    let mut at = vec![Vec::new(); mesh.nodes.len()];
    for (e, &[a, b]) in mesh.boundary.iter().enumerate() {
        at[a].push(e);
        at[b].push(e);
    }
    at
}

fn boundary_node_mask(mesh: &Mesh) -> Vec<bool> {
    let mut on = vec![false; mesh.nodes.len()];
    for &[a, b] in &mesh.boundary {
        on[a] = true;
        on[b] = true;
    }
    on
}

/// Candidate mask of `mesh`'s boundary nodes for a pair: in the region, or near `other`'s boundary.
fn candidates(
    mesh: &Mesh,
    other: &Mesh,
    region: Option<&[f64; 4]>,
    reach: f64,
    tol: f64,
) -> Vec<bool> {
    let on = boundary_node_mask(mesh);
    mesh.nodes
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            on[i]
                && match region {
                    Some(r) => geometry::in_box(p, r, tol),
                    None => other.boundary.iter().any(|&[a, b]| {
                        geometry::project_on_segment(p, other.nodes[a], other.nodes[b]).1 <= reach
                    }),
                }
        })
        .collect()
}

/// A master segment faces a slave node when cos(angle between their outward normals) < −FACING.
const FACING: f64 = 0.3;

fn outward_normal(a: Point, b: Point) -> Point {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len = dx.hypot(dy);
    [dy / len, -dx / len]
}

/// Builds every pair's rows.
pub fn contact_rows(scene: &Scene, meshes: &[Mesh]) -> Result<Vec<PairRows>, ContactError> {
    let tol = scene.tolerance();
    let mut all = Vec::with_capacity(scene.contacts.len());
    for (p, pair) in scene.contacts.iter().enumerate() {
        let [k, l] = pair.bodies;
        let reach = scene.bodies[k].hmax.max(scene.bodies[l].hmax);
        let region = pair.region.as_ref();
        let cand_k = candidates(&meshes[k], &meshes[l], region, reach, tol);
        let cand_l = candidates(&meshes[l], &meshes[k], region, reach, tol);
        let count = |c: &[bool]| c.iter().filter(|x| **x).count();
        let (nk, nl) = (count(&cand_k), count(&cand_l));
        if let Some(r) = region {
            for (n, b) in [(nk, k), (nl, l)] {
                if n == 0 {
                    return Err(ContactError::EmptyRegion {
                        pair: p + 1,
                        region: *r,
                        body: scene.bodies[b].name.clone(),
                    });
                }
            }
        }
        let slave = pair.slave.unwrap_or(if nl > nk { l } else { k });
        let master = if slave == k { l } else { k };
        let (cand_s, cand_m) = if slave == k {
            (&cand_k, &cand_l)
        } else {
            (&cand_l, &cand_k)
        };
        let rows = pair_rows(&meshes[slave], &meshes[master], cand_s, cand_m, tol);
        // Conforming: every slave node on the interface (zero gap) sits on a master node.
        let touching: Vec<&ContactRow> = rows.iter().filter(|r| r.gap == 0.0).collect();
        let conforming =
            !touching.is_empty() && touching.iter().all(|r| r.alpha == 0.0 || r.alpha == 1.0);
        all.push(PairRows {
            pair: p,
            slave,
            master,
            rows,
            conforming,
        });
    }
    Ok(all)
}

fn pair_rows(
    slave: &Mesh,
    master: &Mesh,
    cand_s: &[bool],
    cand_m: &[bool],
    tol: f64,
) -> Vec<ContactRow> {
    // Master segments: boundary edges with both ends candidates.
    let segments: Vec<[usize; 2]> = master
        .boundary
        .iter()
        .copied()
        .filter(|&[a, b]| cand_m[a] && cand_m[b])
        .collect();
    let slave_edges = edges_at_nodes(slave);
    let mut rows = Vec::new();
    for (x_node, &x) in slave.nodes.iter().enumerate() {
        if !cand_s[x_node] {
            continue;
        }
        // The slave's outward normal at X, from its adjacent interface edges (all adjacent
        // boundary edges if none): only master segments facing it can be touched.
        let mut ns = [0.0, 0.0];
        for pass in [true, false] {
            for &e in &slave_edges[x_node] {
                let [p, q] = slave.boundary[e];
                if pass && !(cand_s[p] && cand_s[q]) {
                    continue;
                }
                let n = outward_normal(slave.nodes[p], slave.nodes[q]);
                ns = [ns[0] + n[0], ns[1] + n[1]];
            }
            if ns != [0.0, 0.0] {
                break;
            }
        }
        let ns_len = ns[0].hypot(ns[1]);
        // Closest facing segment whose span (within tolerance) contains the projection of X.
        let mut best: Option<(f64, bool, [usize; 2], f64)> = None;
        for &[a, b] in &segments {
            let (pa, pb) = (master.nodes[a], master.nodes[b]);
            let nm = outward_normal(pa, pb);
            if ns_len > 0.0 && (nm[0] * ns[0] + nm[1] * ns[1]) / ns_len > -FACING {
                continue;
            }
            let d = [pb[0] - pa[0], pb[1] - pa[1]];
            let len2 = d[0] * d[0] + d[1] * d[1];
            if len2 == 0.0 {
                continue;
            }
            let len = len2.sqrt();
            let t_raw = ((x[0] - pa[0]) * d[0] + (x[1] - pa[1]) * d[1]) / len2;
            let eps = tol / len;
            if t_raw < -eps || t_raw > 1.0 + eps {
                continue;
            }
            let t = if t_raw <= eps {
                0.0
            } else if t_raw >= 1.0 - eps {
                1.0
            } else {
                t_raw
            };
            let y = [pa[0] + t * d[0], pa[1] + t * d[1]];
            let dist = geometry::distance(x, y);
            let interior = t > 0.0 && t < 1.0;
            let better = match best {
                None => true,
                Some((bd, bi, _, _)) => dist < bd - tol || (dist <= bd + tol && interior && !bi),
            };
            if better {
                best = Some((dist, interior, [a, b], t));
            }
        }
        let Some((_, _, [a, b], t)) = best else {
            continue;
        };
        let (pa, pb) = (master.nodes[a], master.nodes[b]);
        let normal = outward_normal(pa, pb);
        let y = [pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1])];
        let gap = (x[0] - y[0]) * normal[0] + (x[1] - y[1]) * normal[1];
        // Tributary length: half of each adjacent interface edge that faces the master (its
        // outward normal opposes n); a side edge caught by a thin region box does not count.
        let mut facing = 0.0;
        let mut interface = 0.0;
        let mut any = 0.0;
        for &e in &slave_edges[x_node] {
            let [p, q] = slave.boundary[e];
            let (pp, pq) = (slave.nodes[p], slave.nodes[q]);
            let half = 0.5 * geometry::distance(pp, pq);
            any += half;
            if cand_s[p] && cand_s[q] {
                interface += half;
                let ns = outward_normal(pp, pq);
                if ns[0] * normal[0] + ns[1] * normal[1] < -0.5 {
                    facing += half;
                }
            }
        }
        let tributary = [facing, interface, any]
            .into_iter()
            .find(|l| *l > 0.0)
            .unwrap_or(1.0);
        rows.push(ContactRow {
            slave_node: x_node,
            master_nodes: [a, b],
            alpha: 1.0 - t,
            normal,
            gap: if gap.abs() <= tol { 0.0 } else { gap },
            tributary,
            position: x,
        });
    }
    rows
}
