//! Contact constraints: node-to-segment (this file) and mortar (`contact/mortar/mod.rs`), chosen
//! per pair by `[[contact]] formulation`.  Both share what is written here about candidates, the
//! slave choice and initial overlaps, and give one row per slave node (`ContactRow`); they differ
//! in how a row's master weights, normal, gap and pressure weight are computed.
//!
//! # Node-to-segment
//!
//! For each contact pair, candidate boundary nodes are those in the pair's region box (or, with no
//! box, within one element size of the other body).  The side with more candidates is the slave
//! (unless the scene names it).  The master's candidate segments are its boundary edges with both
//! ends candidates and, with a box, those that cross it (`master_segments`).  Each slave node X is projected onto the closest master segment
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
//!
//! # Initial overlap
//!
//! A slave node that starts strictly inside the master body (deeper than the scene tolerance) is
//! always a candidate (with no region box) and always gets a row, on the closest master boundary
//! segment whatever its orientation (candidate or not), with a negative gap g: the constraint
//! pushes it out.  One that a region box leaves out is refused
//! ([`ContactError::OverlapOutsideRegion`]): it would stay inside.  The pair's
//! [`Overlap`] records how many nodes start inside and the deepest one.  An overlap deeper than
//! the larger `hmax` of the pair ([`Interface::overlap_limit`]) is not read as contact but refused
//! ([`ContactError::DeepOverlap`]): a linearised node-to-segment row cannot undo it, and such a
//! scene almost always has a misplaced polygon.
//!
//! A node outside the master gets a row only on a segment that faces it and whose line it is not
//! behind (g ≥ −tolerance): a projection through the master body (onto its far side) is no
//! contact.  Candidates without any such segment are counted ([`PairRows::unmatched`]), never
//! silently dropped.
//!
//! # Cost
//!
//! Every search above is defined as a scan of all master segments per slave node, and a scan
//! is what it first was: O(m²) for m interface nodes, which made a long interface (a strip on a
//! foundation, every node a candidate) spend most of its preparation here.  The scans are now
//! narrowed by R-trees of the segments' boxes (`search.rs`): the closest admissible segment is
//! found by walking outwards from the node, then only the segments within its distance (plus
//! the tolerance chain the tie-breaks can climb, plus a rounding margin) are evaluated, in the
//! scan's order, with the scan's arithmetic — so the rows are bit-identical to the scan's
//! (same rows, order, gaps, weights, normals, tributary lengths; the scan is kept as a
//! test-only oracle and compared bit for bit on random, degenerate and fixture geometries).
//! The same holds for the overlap depths (nearest boundary segment) and, without a region box,
//! the candidate test (a segment within `hmax`).  Cost: O(log m) per node that has an
//! admissible segment nearby; a node with none (counted in [`PairRows::unmatched`]) searches,
//! past a short walk, only the cone in front of it where a facing segment could lie, so a
//! region box drawn over whole bodies (whose far sides face nothing) stays O(m log m) too.
//!
//! Measured with `signorini check` (mesh + assemble, no solve) on
//! `sh scripts/strip-scene.sh --length L --foundation-layers 4`, old and new binaries run
//! alternately in one session on the shared 2-core machine (load 4–5 from other builds):
//!
//! | L | rows m | free DOFs | before | after | speed-up |
//! |---|---|---|---|---|---|
//! | 25 | 2 501 | 64 465 | 0.38 s | 0.13 s | 2.9× |
//! | 50 | 5 001 | 128 903 | 1.37 s | 0.35 s | 3.9× |
//! | 100 | 10 001 | 257 795 | 4.42 s | 0.60 s | 7.4× |
//! | 200 | 20 001 | 515 577 | 16.5 s | 1.81 s | 9.1× |
//! | 400 | 40 001 | 1 031 129 | 78.3 s | 6.82 s | 11.5× |
//!
//! With the contact box widened to both bodies' whole height (`region = [0, L, 0.96, 1.02]`,
//! every boundary node a candidate, the far sides unmatched): L = 50, 1.38 s → 0.26 s;
//! L = 100, 7.28 s → 0.94 s.  Repeated runs of one binary vary by up to 1.5× on this shared
//! machine (other helpers' builds); the rows of each table line come from one alternating run.
//!
//! What remains superlinear is the P1 mesher's Delaunay bulk load (see [`crate::mesh`]): 25 %
//! of the new time at L = 100, 61 % at L = 400.

mod deformed;
mod interface;
mod mortar;
mod overlap;
mod search;
#[cfg(test)]
mod tests;

pub use deformed::{deformed_check, deformed_overlap, DeformedCheck, DeformedOverlap, Unjudged};
pub use interface::{Interface, Side};
pub use overlap::Overlap;

use crate::geometry::{self, Point};
use crate::mesh::Mesh;
use crate::scene::{Formulation, Friction};
use overlap::{deepest, depths_inside, strictly_inside};
use search::{Cone, SegmentIndex};

/// One constraint row.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactRow {
    /// Slave node (body-local index).
    pub slave_node: usize,
    /// The master nodes the row couples the slave node to, with their weights (body-local
    /// indices; the weights sum to one, so a rigid translation of both bodies leaves the row
    /// unchanged).  Node-to-segment: the segment's ends `[(A, α), (B, 1 − α)]`; mortar: every
    /// master node whose segments the slave node's dual basis function meets, weight
    /// M_jk / D_jj.  Zero weights may appear and give no entry of B.
    pub masters: Vec<(usize, f64)>,
    /// Unit normal n of the row, pointing out of the master towards the slave: the row is
    /// −n·u_X + Σₖ wₖ n·u_k ≤ g.  Node-to-segment: the master segment's outward normal; mortar:
    /// the ψ-weighted mean of the outward normals of the master segments the node's dual basis
    /// function meets.
    pub normal: Point,
    /// Initial normal gap g (node-to-segment: (X − Y)·n; mortar: the weighted gap g̃_j / D_jj).
    pub gap: f64,
    /// The length that turns the row's multiplier (a force per unit thickness) into a pressure:
    /// node-to-segment, the slave node's tributary length on the interface; mortar, D_jj = ∫N_j
    /// over the part of the slave interface the master covers.
    pub tributary: f64,
    /// Slave node position X.
    pub position: Point,
    /// k = (t·d)/(n·d), d the direction along which the slave node was paired with the master
    /// (its own normal), t and n the row's tangent and normal: the paired points lie k × the
    /// normal gap apart along t, and a node closing its gap along d moves k per unit of normal
    /// gap along t without slipping.  Used by frictional rows only (the tangential row's
    /// reference, `model::friction`); 0 where the row's normal is the pairing direction
    /// (node-to-segment) and on frictionless pairs.
    pub pairing_slope: f64,
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
    /// How the rows were built.
    pub formulation: Formulation,
    /// The pair's friction law (`None`: frictionless, no tangential rows).
    pub friction: Option<Friction>,
    /// Constraint rows, ordered by slave node.
    pub rows: Vec<ContactRow>,
    /// True when every slave node on the interface (zero initial gap) coincides with a master node.
    pub conforming: bool,
    /// Number of slave candidate nodes (each either has a row or is counted in `unmatched`).
    pub candidates: usize,
    /// Slave candidates that got no row: no master segment faces them (within its span, on
    /// its outer side).
    pub unmatched: usize,
    /// Rows whose tributary length is not the half-lengths of slave edges facing the master
    /// (it falls back to the other interface edges, then to every adjacent boundary edge, then to
    /// 1.0): their pressure λ / length is an estimate.
    pub tributary_fallbacks: usize,
    /// Of `tributary_fallbacks`, the rows whose node has no boundary edge of positive length, so
    /// that the length 1.0 was used.
    pub unit_tributaries: usize,
    /// The bodies' initial overlap, if any boundary node starts inside the other body.
    pub overlap: Option<Overlap>,
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
    /// Two bodies of a pair overlap too deeply at the start to be read as contact.
    #[error("contact #{pair}: body \"{body}\" starts inside body \"{other}\": its boundary node at ({x}, {y}) lies {depth:e} deep, more than the larger element size {limit:e} of the pair; an overlap this deep is not a contact (move the bodies apart)", x = point[0], y = point[1])]
    DeepOverlap {
        /// 1-based pair index.
        pair: usize,
        /// Body whose node is inside the other.
        body: String,
        /// The body it is inside.
        other: String,
        /// The node's position.
        point: Point,
        /// Its distance to `other`'s boundary.
        depth: f64,
        /// The largest accepted depth ([`Interface::overlap_limit`]).
        limit: f64,
    },
    /// Slave nodes start inside the master outside the pair's region box, so no row can push
    /// them out.
    #[error("contact #{pair}: {nodes} boundary node(s) of slave \"{slave}\" start inside master \"{master}\" outside the pair's region box (deepest {depth:e} at ({x}, {y})), so no constraint row can push them out; enlarge the region to cover the overlap or move the bodies apart", x = point[0], y = point[1])]
    OverlapOutsideRegion {
        /// 1-based pair index.
        pair: usize,
        /// Slave body name.
        slave: String,
        /// Master body name.
        master: String,
        /// Slave nodes inside the master without a row.
        nodes: usize,
        /// The deepest one's position.
        point: Point,
        /// Its depth.
        depth: f64,
    },
    /// Only master nodes start inside the slave: node-to-segment rows constrain slave nodes, so
    /// nothing would push them out.
    #[error("contact #{pair}: {nodes} boundary node(s) of master \"{master}\" start inside slave \"{slave}\" (deepest {depth:e} at ({x}, {y})) and no slave node starts inside the master; node-to-segment rows constrain only slave nodes, so nothing would push them out: set slave = \"{master}\" or move the bodies apart", x = point[0], y = point[1])]
    MasterInsideSlave {
        /// 1-based pair index.
        pair: usize,
        /// Slave body name.
        slave: String,
        /// Master body name.
        master: String,
        /// Master nodes inside the slave.
        nodes: usize,
        /// The deepest one's position.
        point: Point,
        /// Its depth.
        depth: f64,
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

/// True for each node on a boundary edge.
fn boundary_node_mask(mesh: &Mesh) -> Vec<bool> {
    let mut on = vec![false; mesh.nodes.len()];
    for &[a, b] in &mesh.boundary {
        on[a] = true;
        on[b] = true;
    }
    on
}

/// Candidate mask of `mesh`'s boundary nodes for a pair: in the region, or (no region) near
/// `other`'s boundary or inside `other` (`inside`, from [`depths_inside`]).
///
/// "Near" is: some boundary edge of `other` at distance ≤ `reach` (by
/// [`geometry::project_on_segment`]).  [`Search::Indexed`] tests only the edges an R-tree finds
/// within `reach` plus a rounding margin — every edge that can pass — so the mask is the scan's.
fn candidates(
    mesh: &Mesh,
    other: &Mesh,
    region: Option<&[f64; 4]>,
    reach: f64,
    tol: f64,
    inside: &[Option<f64>],
    search: Search,
) -> Vec<bool> {
    let on = boundary_node_mask(mesh);
    let index = match (region, search) {
        (None, Search::Indexed) => Some(SegmentIndex::new(&other.nodes, &other.boundary)),
        _ => None,
    };
    let near = |p: Point, e: usize| {
        let [a, b] = other.boundary[e];
        geometry::project_on_segment(p, other.nodes[a], other.nodes[b]).1 <= reach
    };
    mesh.nodes
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            on[i]
                && match region {
                    Some(r) => geometry::in_box(p, r, tol),
                    None => {
                        strictly_inside(inside[i], tol)
                            || match &index {
                                Some(index) => index.within(p, reach).any(|e| near(p, e)),
                                None => (0..other.boundary.len()).any(|e| near(p, e)),
                            }
                    }
                }
        })
        .collect()
}

/// The master's candidate segments: boundary edges with both ends candidates and, with a region
/// box, every boundary edge that runs through the box (longer than the tolerance inside it) with
/// no end left out inside it (by a `group`).
///
/// A box that cuts a master segment leaves one end outside: the segment still bounds the master
/// where the box is, and without it a slave node facing its inner part had no row and sank in
/// (found by the fuzz harness: a region box ending between two nodes of a coarse Gmsh master).
/// An edge that only touches the box at a candidate corner adds nothing inside it, and taking it
/// would turn that corner's row onto it (the shoulders of `fixtures/hard/inclined.toml`, whose
/// box is the slope's bounding box).
fn master_segments(
    master: &Mesh,
    cand_m: &[bool],
    region: Option<&[f64; 4]>,
    tol: f64,
) -> Vec<[usize; 2]> {
    master
        .boundary
        .iter()
        .copied()
        .filter(|&[a, b]| {
            (cand_m[a] && cand_m[b])
                || region.is_some_and(|r| {
                    let (pa, pb) = (master.nodes[a], master.nodes[b]);
                    let kept = |n: usize, p: Point| cand_m[n] || !geometry::in_box(p, r, tol);
                    let through = geometry::clip_to_box(pa, pb, r, 0.0).is_some_and(|l| l > tol);
                    kept(a, pa) && kept(b, pb) && through
                })
        })
        .collect()
}

/// A master segment faces a slave node when cos(angle between their outward normals) < −FACING.
const FACING: f64 = 0.3;

/// Segments the indexed search visits outwards from a slave node before it restricts the search
/// to where an admissible segment can lie.
const WALK: usize = 32;

fn outward_normal(a: Point, b: Point) -> Point {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len = dx.hypot(dy);
    [dy / len, -dx / len]
}

/// How the closest segments are found: through an R-tree, or (test-only oracle) by scanning
/// every segment, as the search was first written.  Both give bit-identical results.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Search {
    /// R-tree queries narrowing the scan (O(log n) per node).
    Indexed,
    /// Every segment for every node (O(n) per node): the reference the index is tested against.
    #[cfg(test)]
    BruteForce,
}

/// Builds every pair's rows (`tol`: the scene's geometric tolerance).
pub fn contact_rows(
    interfaces: &[Interface<'_>],
    meshes: &[Mesh],
    tol: f64,
) -> Result<Vec<PairRows>, ContactError> {
    contact_rows_with(interfaces, meshes, tol, Search::Indexed)
}

/// [`contact_rows`] with a chosen search.
fn contact_rows_with(
    interfaces: &[Interface<'_>],
    meshes: &[Mesh],
    tol: f64,
    search: Search,
) -> Result<Vec<PairRows>, ContactError> {
    interfaces
        .iter()
        .enumerate()
        .map(|(p, it)| {
            let pair = PairSearch {
                number: p + 1,
                it,
                meshes,
                tol,
                search,
            };
            pair.rows(p)
        })
        .collect()
}

/// One pair's search: its interface, the meshes, the tolerance and the search method.
struct PairSearch<'s, 'a> {
    /// 1-based pair number (for messages).
    number: usize,
    it: &'s Interface<'a>,
    meshes: &'s [Mesh],
    tol: f64,
    search: Search,
}

/// Per side of a pair (in the scene's order): each boundary node's depth inside the other body,
/// and which nodes are candidates.
struct Sides {
    inside: [Vec<Option<f64>>; 2],
    candidates: [Vec<bool>; 2],
}

impl PairSearch<'_, '_> {
    /// The name of body `b`.
    fn name(&self, b: usize) -> String {
        self.it.side(b).name.to_string()
    }

    /// The pair's rows, or why it is refused: initial overlaps first (too deep, master inside
    /// slave, slave nodes stranded outside the region), then the rows themselves.
    fn rows(&self, p: usize) -> Result<PairRows, ContactError> {
        let [sk, sl] = &self.it.sides;
        let (k, l) = (sk.body, sl.body);
        let inside = [
            depths_inside(
                &self.meshes[k],
                &self.meshes[l],
                sl.outline,
                self.tol,
                self.search,
            ),
            depths_inside(
                &self.meshes[l],
                &self.meshes[k],
                sk.outline,
                self.tol,
                self.search,
            ),
        ];
        let deepest_all = self.refuse_deep_overlap(&inside)?;
        let sides = Sides {
            candidates: self.candidates(&inside)?,
            inside,
        };
        let (slave, master) = self.choose_slave(&sides);
        let (s, m) = if slave == k { (0, 1) } else { (1, 0) };
        self.refuse_master_inside_slave(slave, master, &sides.inside[s], &sides.inside[m])?;
        let segments = master_segments(
            &self.meshes[master],
            &sides.candidates[m],
            self.it.region.as_ref(),
            self.tol,
        );
        let built = self.build(
            slave,
            master,
            &sides.candidates[s],
            &segments,
            &sides.inside[s],
        );
        let with_row = self.refuse_stranded(slave, master, &built.rows, &sides.inside[s])?;
        let overlap = deepest_all.map(|(b, _, i, depth)| {
            let tol = self.tol;
            let inside = |d: &&Option<f64>| strictly_inside(**d, tol);
            let slave_nodes = sides.inside[s]
                .iter()
                .zip(&with_row)
                .filter(|(d, w)| strictly_inside(**d, tol) && **w)
                .count();
            Overlap {
                slave_nodes,
                master_nodes: sides.inside[m].iter().filter(inside).count(),
                deepest: self.meshes[b].nodes[i],
                depth,
                deepest_body: b,
            }
        });
        let count = |c: &[bool]| c.iter().filter(|x| **x).count();
        Ok(PairRows {
            pair: p,
            slave,
            master,
            formulation: self.it.formulation,
            friction: self.it.friction,
            conforming: conforming(&built.rows),
            rows: built.rows,
            candidates: count(&sides.candidates[s]),
            unmatched: built.unmatched,
            tributary_fallbacks: built.tributary_fallbacks,
            unit_tributaries: built.unit_tributaries,
            overlap,
        })
    }

    /// The deepest initial overlap of either body in the other (body, other, node, depth);
    /// refused beyond [`Interface::overlap_limit`].
    fn refuse_deep_overlap(
        &self,
        inside: &[Vec<Option<f64>>; 2],
    ) -> Result<Option<(usize, usize, usize, f64)>, ContactError> {
        let (k, l) = (self.it.sides[0].body, self.it.sides[1].body);
        let deepest_k = deepest(&inside[0], self.tol).map(|(i, d)| (k, l, i, d));
        let deepest_l = deepest(&inside[1], self.tol).map(|(i, d)| (l, k, i, d));
        let deepest_all = match (deepest_k, deepest_l) {
            (Some(a), Some(b)) => Some(if b.3 > a.3 { b } else { a }),
            (a, b) => a.or(b),
        };
        let limit = self.it.overlap_limit();
        if let Some((b, o, i, depth)) = deepest_all {
            if depth > limit {
                return Err(ContactError::DeepOverlap {
                    pair: self.number,
                    body: self.name(b),
                    other: self.name(o),
                    point: self.meshes[b].nodes[i],
                    depth,
                    limit,
                });
            }
        }
        Ok(deepest_all)
    }

    /// Each side's candidate nodes: near the other body (within the larger `hmax`), in the
    /// region box and the pair's group; a region box that holds none of a body's is refused.
    fn candidates(&self, inside: &[Vec<Option<f64>>; 2]) -> Result<[Vec<bool>; 2], ContactError> {
        let it = self.it;
        let reach = it.overlap_limit();
        let region = it.region.as_ref();
        let mut candidates = [0, 1].map(|i| {
            let (own, other) = (it.sides[i].body, it.sides[1 - i].body);
            let (mesh, other) = (&self.meshes[own], &self.meshes[other]);
            candidates(
                mesh,
                other,
                region,
                reach,
                self.tol,
                &inside[i],
                self.search,
            )
        });
        // `group`: each body whose Gmsh mesh defines the group keeps only the group's nodes.
        for (cand, side) in candidates.iter_mut().zip(&it.sides) {
            if let Some(g) = side.group {
                for (n, c) in cand.iter_mut().enumerate() {
                    *c = *c && g.has_node(n);
                }
            }
        }
        if let Some(r) = region {
            for (cand, side) in candidates.iter().zip(&it.sides) {
                if !cand.iter().any(|c| *c) {
                    return Err(ContactError::EmptyRegion {
                        pair: self.number,
                        region: *r,
                        body: side.name.to_string(),
                    });
                }
            }
        }
        Ok(candidates)
    }

    /// (slave, master): the scene's choice; else the body whose nodes alone start inside the
    /// other (an initial overlap is undone by slave rows only); else the one with more
    /// candidates (the first on a tie).
    fn choose_slave(&self, sides: &Sides) -> (usize, usize) {
        let (k, l) = (self.it.sides[0].body, self.it.sides[1].body);
        let tol = self.tol;
        let count = |c: &[bool]| c.iter().filter(|x| **x).count();
        let inside_count =
            |d: &[Option<f64>]| d.iter().filter(|x| strictly_inside(**x, tol)).count();
        let (nk, nl) = (count(&sides.candidates[0]), count(&sides.candidates[1]));
        let (ik, il) = (
            inside_count(&sides.inside[0]),
            inside_count(&sides.inside[1]),
        );
        let slave = self.it.slave.unwrap_or(match (ik > 0, il > 0) {
            (true, false) => k,
            (false, true) => l,
            _ if nl > nk => l,
            _ => k,
        });
        (slave, if slave == k { l } else { k })
    }

    /// Refuses a pair where only master nodes start inside the slave: node-to-segment rows
    /// constrain slave nodes only, so nothing would push them out.
    fn refuse_master_inside_slave(
        &self,
        slave: usize,
        master: usize,
        inside_s: &[Option<f64>],
        inside_m: &[Option<f64>],
    ) -> Result<(), ContactError> {
        let inside_count =
            |d: &[Option<f64>]| d.iter().filter(|x| strictly_inside(**x, self.tol)).count();
        if inside_count(inside_s) == 0 {
            if let Some((i, depth)) = deepest(inside_m, self.tol) {
                return Err(ContactError::MasterInsideSlave {
                    pair: self.number,
                    slave: self.name(slave),
                    master: self.name(master),
                    nodes: inside_count(inside_m),
                    point: self.meshes[master].nodes[i],
                    depth,
                });
            }
        }
        Ok(())
    }

    /// The rows of the pair's formulation.
    fn build(
        &self,
        slave: usize,
        master: usize,
        cand_s: &[bool],
        segments: &[[usize; 2]],
        inside_s: &[Option<f64>],
    ) -> Built {
        let (ms, mm) = (&self.meshes[slave], &self.meshes[master]);
        let limit = self.it.overlap_limit();
        match self.it.formulation {
            Formulation::NodeToSegment => pair_rows(
                ms,
                mm,
                cand_s,
                segments,
                inside_s,
                self.tol,
                limit,
                self.search,
            ),
            Formulation::Mortar => {
                // Frictional pairs act along the interface's normal (see mortar::Frame).
                let frame = if self.it.friction.is_some() {
                    mortar::Frame::Interface {
                        slave: self.it.side(slave).compliance,
                        master: self.it.side(master).compliance,
                    }
                } else {
                    mortar::Frame::Master
                };
                mortar::pair_rows(ms, mm, cand_s, segments, inside_s, self.tol, limit, frame)
            }
        }
    }

    /// Which slave nodes have a row; refuses slave nodes inside the master without one
    /// (outside the region box): they would stay interpenetrating.
    fn refuse_stranded(
        &self,
        slave: usize,
        master: usize,
        rows: &[ContactRow],
        inside_s: &[Option<f64>],
    ) -> Result<Vec<bool>, ContactError> {
        let mut with_row = vec![false; self.meshes[slave].nodes.len()];
        for r in rows {
            with_row[r.slave_node] = true;
        }
        let stranded = inside_s
            .iter()
            .zip(&with_row)
            .enumerate()
            .filter(|(_, (d, w))| strictly_inside(**d, self.tol) && !**w)
            .map(|(i, (d, _))| (i, d.unwrap_or(0.0)));
        let (mut count_stranded, mut worst) = (0, None);
        for (i, d) in stranded {
            count_stranded += 1;
            if worst.is_none_or(|(_, wd)| d > wd) {
                worst = Some((i, d));
            }
        }
        if let Some((i, depth)) = worst {
            return Err(ContactError::OverlapOutsideRegion {
                pair: self.number,
                slave: self.name(slave),
                master: self.name(master),
                nodes: count_stranded,
                point: self.meshes[slave].nodes[i],
                depth,
            });
        }
        Ok(with_row)
    }
}

/// Conforming: every slave node on the interface (zero gap) sits on a master node.
fn conforming(rows: &[ContactRow]) -> bool {
    let touching: Vec<&ContactRow> = rows.iter().filter(|r| r.gap == 0.0).collect();
    !touching.is_empty()
        && touching
            .iter()
            .all(|r| r.masters.iter().any(|&(_, w)| (w - 1.0).abs() <= 1e-12))
}

/// The rows of one pair with the counts of what could not be done exactly.
struct Built {
    rows: Vec<ContactRow>,
    unmatched: usize,
    tributary_fallbacks: usize,
    unit_tributaries: usize,
}

/// The closest admissible master segment for one slave node: (distance, interior projection,
/// facing, segment, t).
type Choice = (f64, bool, bool, [usize; 2], f64);

/// One slave node's search for its master segment.
struct Probe {
    /// The node X.
    x: Point,
    /// The slave's outward normal at X (unnormalised; zero when unknown).
    ns: Point,
    /// |ns|.
    ns_len: f64,
    /// X starts strictly inside the master.
    inside: bool,
    /// How far behind a segment's line X may lie (outside only).
    behind_limit: f64,
    /// Length tolerance of the scene.
    tol: f64,
}

impl Probe {
    /// Segment a–b (master nodes) seen from X: `None` when not admissible, otherwise
    /// (distance, interior projection, facing, t).
    ///
    /// Outside the master: the segment must face X, its span (within tolerance) contain the
    /// projection of X and X not lie behind its line.  Inside: any segment of positive length,
    /// projection clamped to it.
    fn evaluate(&self, pa: Point, pb: Point) -> Option<(f64, bool, bool, f64)> {
        #[cfg(test)]
        tests::EVALUATIONS.with(|c| c.set(c.get() + 1));
        let (x, ns, tol) = (self.x, self.ns, self.tol);
        let nm = outward_normal(pa, pb);
        let facing = self.ns_len == 0.0 || (nm[0] * ns[0] + nm[1] * ns[1]) / self.ns_len <= -FACING;
        if !self.inside && !facing {
            return None;
        }
        let d = [pb[0] - pa[0], pb[1] - pa[1]];
        let len2 = d[0] * d[0] + d[1] * d[1];
        if len2 == 0.0 {
            return None;
        }
        let len = len2.sqrt();
        let t_raw = ((x[0] - pa[0]) * d[0] + (x[1] - pa[1]) * d[1]) / len2;
        let eps = tol / len;
        if !self.inside && (t_raw < -eps || t_raw > 1.0 + eps) {
            return None;
        }
        let t = if t_raw <= eps {
            0.0
        } else if t_raw >= 1.0 - eps {
            1.0
        } else {
            t_raw
        };
        let y = [pa[0] + t * d[0], pa[1] + t * d[1]];
        if !self.inside && (x[0] - y[0]) * nm[0] + (x[1] - y[1]) * nm[1] < -self.behind_limit {
            // Behind the segment's line yet outside the master (or deeper than the overlap
            // limit while on its boundary): the projection runs through the body to its far
            // side.
            return None;
        }
        let dist = geometry::distance(x, y);
        Some((dist, t > 0.0 && t < 1.0, facing, t))
    }

    /// The choice among `segments` (master node pairs) visited in the order `order`: each
    /// admissible segment replaces the running best when it is closer by more than the
    /// tolerance, or as close within the tolerance and better placed (an interior projection
    /// over an end, then a facing segment over a non-facing one).
    fn select(
        &self,
        master: &Mesh,
        segments: &[[usize; 2]],
        order: impl IntoIterator<Item = usize>,
    ) -> Option<Choice> {
        let tol = self.tol;
        let mut best: Option<Choice> = None;
        for s in order {
            let [a, b] = segments[s];
            let Some((dist, interior, facing, t)) = self.evaluate(master.nodes[a], master.nodes[b])
            else {
                continue;
            };
            let better = match best {
                None => true,
                Some((bd, bi, bf, _, _)) => {
                    dist < bd - tol
                        || (dist <= bd + tol
                            && ((interior && !bi) || (interior == bi && facing && !bf)))
                }
            };
            if better {
                best = Some((dist, interior, facing, [a, b], t));
            }
        }
        best
    }

    /// [`Probe::select`] over every segment in list order, through the R-tree `index` of
    /// `segments`: the same choice, from the few segments near X.
    ///
    /// Why it is the same: let D be the distance of the closest admissible segment and T ≥ D a
    /// threshold such that no admissible segment lies at a distance in (T, T + tol].  Visit, in
    /// list order, only the admissible segments at distance ≤ T (the set S).  In the full scan,
    /// once the first member of S has been visited the running best is a member of S: it
    /// replaces any earlier best (which is beyond T + tol, so farther by more than tol), and no
    /// segment beyond T + tol can replace a member of S (it is neither closer by tol nor within
    /// tol).  Between members of S the comparisons are the scan's own.  So the scan ends on the
    /// choice the visit of S alone makes.  The index finds an admissible segment by walking
    /// outwards from X (an upper bound on D), then every segment within a radius by a box
    /// query with a rounding margin; T starts at D and is raised over any admissible distance
    /// within tol above it, widening the query when needed.
    ///
    /// Cost: O(log n) per node with a nearby admissible segment.  A node without one, outside
    /// the master, searches only the cone where a facing segment it is not behind can lie
    /// ([`Probe::cone`]), so a node whose cone holds no segment (the top of a strip inside a
    /// region box that covers the whole strip) costs O(log n) too.
    /// The distance of some admissible segment (an upper bound of the closest one's), or `None`
    /// when there is none.  Walks outwards from X over the first [`WALK`] segments; past them
    /// (outside the master, slave normal known) searches the cone of [`Probe::cone`] in discs
    /// of doubling radius until the disc holds every segment.
    fn first_admissible(
        &self,
        index: &SegmentIndex,
        distance_of: impl Fn(usize) -> Option<f64>,
    ) -> Option<f64> {
        let mut walked = 0;
        let mut reached = 0.0;
        let mut nearest = index.nearest(self.x);
        for (s, d) in nearest.by_ref() {
            if let Some(d) = distance_of(s) {
                return Some(d);
            }
            walked += 1;
            reached = d;
            if walked == WALK {
                break;
            }
        }
        if walked < WALK {
            return None;
        }
        if self.inside || self.ns_len == 0.0 {
            // Any direction may hold the segment: walk on.
            return nearest.find_map(|(s, _)| distance_of(s));
        }
        let farthest = index.farthest(self.x);
        let mut radius = reached.max(self.tol).max(f64::MIN_POSITIVE);
        loop {
            let cone = self.cone(radius, index.margin(self.x, radius));
            let found = index
                .in_cone(&cone)
                .filter_map(&distance_of)
                .fold(None, |m: Option<f64>, d| Some(m.map_or(d, |m| m.min(d))));
            if found.is_some() || radius > farthest {
                return found;
            }
            radius *= 2.0;
        }
    }

    /// Where an admissible segment can lie when X is outside the master: some point y of it
    /// has x − y = s n_m + w with n_m its unit normal, s ≥ −b (b = `behind_limit`, X not behind
    /// its line), |w| ≤ tol (the projection snapped to an end within tol) and
    /// n_m·u ≤ −FACING (u = n_s / |n_s|, facing).  Then (y − x)·u ≥ FACING |y − x| − 1.3 (b + tol)
    /// whatever the sign of s: y lies in the cone around u of half-angle acos(FACING), its apex
    /// pulled back by 1.3 (b + tol) (1.5 here, for the rounding of u and n_m).
    fn cone(&self, radius: f64, margin: f64) -> Cone {
        Cone {
            apex: self.x,
            axis: [self.ns[0] / self.ns_len, self.ns[1] / self.ns_len],
            cos: FACING * (1.0 - 1e-9),
            slack: 1.5 * (self.behind_limit + self.tol),
            radius,
            margin,
        }
    }

    fn select_indexed(
        &self,
        master: &Mesh,
        segments: &[[usize; 2]],
        index: &SegmentIndex,
    ) -> Option<Choice> {
        let distance_of = |s: usize| {
            let [a, b] = segments[s];
            self.evaluate(master.nodes[a], master.nodes[b])
                .map(|(d, _, _, _)| d)
        };
        let bound = self.first_admissible(index, distance_of)?;
        let tol = self.tol;
        let mut radius = bound + 2.0 * tol;
        loop {
            let mut near: Vec<(f64, usize)> = index
                .within(self.x, radius)
                .filter_map(|s| distance_of(s).map(|d| (d, s)))
                .collect();
            near.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)));
            // `near` holds the segment at `bound`, so it is not empty and starts at D.
            let mut threshold = near.first().map_or(bound, |n| n.0);
            for &(d, _) in &near {
                if d <= threshold {
                    continue;
                }
                if d <= threshold + tol {
                    threshold = d;
                } else {
                    break;
                }
            }
            if threshold + tol <= radius {
                // Every admissible segment within threshold + tol is in `near`.
                let mut set: Vec<usize> = near
                    .iter()
                    .filter(|n| n.0 <= threshold)
                    .map(|n| n.1)
                    .collect();
                set.sort_unstable();
                return self.select(master, segments, set);
            }
            // threshold + tol > radius ≥ 0: the new radius exceeds the old one.
            radius = 2.0 * (threshold + tol);
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn pair_rows(
    slave: &Mesh,
    master: &Mesh,
    cand_s: &[bool],
    segments: &[[usize; 2]],
    inside_s: &[Option<f64>],
    tol: f64,
    limit: f64,
    search: Search,
) -> Built {
    let slave_edges = edges_at_nodes(slave);
    let mut built = Built {
        rows: Vec::new(),
        unmatched: 0,
        tributary_fallbacks: 0,
        unit_tributaries: 0,
    };
    // The R-trees: of the candidate segments (nodes outside the master) and, only when some
    // slave node starts inside, of the whole master boundary.
    let (outside_index, inside_index) = match search {
        Search::Indexed => {
            let any_inside =
                (0..slave.nodes.len()).any(|i| cand_s[i] && strictly_inside(inside_s[i], tol));
            (
                Some(SegmentIndex::new(&master.nodes, segments)),
                any_inside.then(|| SegmentIndex::new(&master.nodes, &master.boundary)),
            )
        }
        #[cfg(test)]
        Search::BruteForce => (None, None),
    };
    for (x_node, &x) in slave.nodes.iter().enumerate() {
        if !cand_s[x_node] {
            continue;
        }
        let inside = strictly_inside(inside_s[x_node], tol);
        // On the master's boundary (within tolerance): a shallow negative gap is an overlap
        // along the boundary; a deep one a projection through the body.
        let behind_limit = if inside_s[x_node].is_some() {
            limit
        } else {
            tol
        };
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
        let probe = Probe {
            x,
            ns,
            ns_len: ns[0].hypot(ns[1]),
            inside,
            behind_limit,
            tol,
        };
        // Outside the master: the closest facing candidate segment whose span (within
        // tolerance) contains the projection of X and whose line X is not behind.  Inside: the
        // closest boundary segment of the master, candidate or not, of any orientation (the
        // shortest way out), projection clamped to the segment.
        let (admissible, index) = if inside {
            (master.boundary.as_slice(), inside_index.as_ref())
        } else {
            (segments, outside_index.as_ref())
        };
        let best = match index {
            Some(index) if !index.is_empty() => probe.select_indexed(master, admissible, index),
            _ => probe.select(master, admissible, 0..admissible.len()),
        };
        let Some((_, _, _, [a, b], t)) = best else {
            built.unmatched += 1;
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
        let tributary = match [facing, interface, any].into_iter().find(|l| *l > 0.0) {
            Some(l) => l,
            None => {
                built.unit_tributaries += 1;
                1.0
            }
        };
        if facing <= 0.0 {
            built.tributary_fallbacks += 1;
        }
        built.rows.push(ContactRow {
            slave_node: x_node,
            masters: vec![(a, 1.0 - t), (b, t)],
            normal,
            gap: if gap.abs() <= tol { 0.0 } else { gap },
            tributary,
            position: x,
            pairing_slope: 0.0,
        });
    }
    built
}
