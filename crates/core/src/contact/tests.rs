//! The indexed contact search against the brute-force scan it replaced ([`Search::BruteForce`],
//! kept as a test-only oracle): bit-identical rows, in the same order, with the same gaps,
//! weights, normals and tributary lengths, on random and on degenerate geometries and on every
//! fixture scene; and the indexed search's cost per node on a long interface.
//!
//! No tolerance appears in the comparisons: results are compared bit for bit (`f64::to_bits`).

#![allow(clippy::unwrap_used, clippy::expect_used)] // tests may unwrap

use super::*;
use crate::mesh::{Cells, Mesh, MeshLimits};
use crate::scene::Scene;
use std::cell::Cell;

/// The rows of a scene's pairs through the contact effect, with a chosen search.
fn scene_rows(
    scene: &Scene,
    meshes: &[Mesh],
    search: Search,
) -> Result<Vec<PairRows>, ContactError> {
    let contact = crate::effects::ContactEffect::of(scene);
    contact_rows_with(&contact.interfaces, meshes, contact.tol, search)
}

thread_local! {
    /// Segments evaluated by [`Probe::evaluate`] on this thread (the search's unit of work).
    pub(super) static EVALUATIONS: Cell<usize> = const { Cell::new(0) };
}

/// A small deterministic generator (SplitMix64), so that every case is reproducible.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// A star-shaped counter-clockwise loop of `n` vertices around `center`, radii in [r/2, r],
/// optionally snapped to a grid of `snap` (which makes coincident vertices, zero-length
/// segments, horizontal and vertical edges and exact distance ties).
fn star(rng: &mut Rng, center: Point, r: f64, n: usize, snap: Option<f64>) -> Vec<Point> {
    let mut angles: Vec<f64> = (0..n)
        .map(|_| rng.range(0.0, std::f64::consts::TAU))
        .collect();
    angles.sort_by(f64::total_cmp);
    angles
        .into_iter()
        .map(|a| {
            let rho = rng.range(0.5 * r, r);
            let p = [center[0] + rho * a.cos(), center[1] + rho * a.sin()];
            match snap {
                Some(g) => [(p[0] / g).round() * g, (p[1] / g).round() * g],
                None => p,
            }
        })
        .collect()
}

/// A row as bits.
type RowBits = (usize, Vec<(usize, u64)>, [u64; 2], u64, u64, [u64; 2]);

fn row_bits(r: &ContactRow) -> RowBits {
    (
        r.slave_node,
        r.masters.iter().map(|&(k, w)| (k, w.to_bits())).collect(),
        r.normal.map(f64::to_bits),
        r.gap.to_bits(),
        r.tributary.to_bits(),
        r.position.map(f64::to_bits),
    )
}

fn built_bits(b: &Built) -> (Vec<RowBits>, usize, usize, usize) {
    (
        b.rows.iter().map(row_bits).collect(),
        b.unmatched,
        b.tributary_fallbacks,
        b.unit_tributaries,
    )
}

fn depth_bits(d: &[Option<f64>]) -> Vec<Option<u64>> {
    d.iter().map(|d| d.map(f64::to_bits)).collect()
}

/// Runs `pair_rows` both ways, asserts bit-identical results and returns the indexed one.
#[allow(clippy::too_many_arguments)]
fn same_rows(
    slave: &Mesh,
    master: &Mesh,
    cand_s: &[bool],
    cand_m: &[bool],
    inside_s: &[Option<f64>],
    tol: f64,
    limit: f64,
    case: &str,
) -> Built {
    let segments = master_segments(master, cand_m, None, tol);
    let fast = pair_rows(
        slave,
        master,
        cand_s,
        &segments,
        inside_s,
        tol,
        limit,
        Search::Indexed,
    );
    let slow = pair_rows(
        slave,
        master,
        cand_s,
        &segments,
        inside_s,
        tol,
        limit,
        Search::BruteForce,
    );
    assert_eq!(built_bits(&fast), built_bits(&slow), "{case}");
    fast
}

/// The whole pipeline of one pair on two loops, both ways: depths inside, candidates (no
/// region, reach `reach`) and rows.  Returns the rows.
fn same_pipeline(slave: &Mesh, master: &Mesh, reach: f64, tol: f64, case: &str) -> Built {
    let polygon_m = master.nodes.clone();
    let polygon_s = slave.nodes.clone();
    let depths = |m: &Mesh, o: &Mesh, poly: &[Point]| {
        let fast = depths_inside(m, o, poly, tol, Search::Indexed);
        let slow = depths_inside(m, o, poly, tol, Search::BruteForce);
        assert_eq!(depth_bits(&fast), depth_bits(&slow), "{case}: depths");
        fast
    };
    let inside_s = depths(slave, master, &polygon_m);
    let inside_m = depths(master, slave, &polygon_s);
    let cands = |m: &Mesh, o: &Mesh, inside: &[Option<f64>]| {
        let fast = candidates(m, o, None, reach, tol, inside, Search::Indexed);
        let slow = candidates(m, o, None, reach, tol, inside, Search::BruteForce);
        assert_eq!(fast, slow, "{case}: candidates");
        fast
    };
    let cand_s = cands(slave, master, &inside_s);
    let cand_m = cands(master, slave, &inside_m);
    same_rows(slave, master, &cand_s, &cand_m, &inside_s, tol, reach, case)
}

#[test]
fn random_geometries_match_the_scan() {
    let mut rng = Rng(0x5EED_0009);
    let mut rows = 0;
    for case in 0..400 {
        let snap = match case % 4 {
            0 => Some(0.25),
            1 => Some(1.0 / 64.0),
            _ => None,
        };
        let ns = 3 + rng.below(60);
        let nm = 3 + rng.below(60);
        let slave = Mesh::boundary_loop(star(&mut rng, [0.0, 0.0], 4.0, ns, snap));
        // Separated, touching or overlapping: the master's centre 0 to 10 away.
        let offset = [rng.range(-10.0, 10.0), rng.range(-10.0, 10.0)];
        let master = Mesh::boundary_loop(star(&mut rng, offset, 4.0, nm, snap));
        // Tolerances from none to very coarse (many near-ties within tol).
        let tol = [0.0, 1e-9, 1e-3, 0.05, 0.5][rng.below(5)];
        let reach = rng.range(0.1, 6.0);
        let case = format!("random case {case} (tol {tol}, reach {reach})");
        rows += same_pipeline(&slave, &master, reach, tol, &case).rows.len();
        // Random candidate masks and depths too, not only the pipeline's own.
        let cand_s: Vec<bool> = (0..ns).map(|_| rng.unit() < 0.8).collect();
        let cand_m: Vec<bool> = (0..nm).map(|_| rng.unit() < 0.8).collect();
        let inside_s: Vec<Option<f64>> = (0..ns)
            .map(|_| match rng.below(3) {
                0 => None,
                1 => Some(0.0),
                _ => Some(rng.range(0.0, 2.0)),
            })
            .collect();
        let limit = rng.range(0.0, 3.0);
        rows += same_rows(
            &slave, &master, &cand_s, &cand_m, &inside_s, tol, limit, &case,
        )
        .rows
        .len();
    }
    // The cases must exercise the row building, not only "unmatched" (measured: thousands).
    assert!(rows > 1000, "only {rows} rows built");
}

/// A strip's bottom (slave, body above) on a foundation's top (master, body below), straight,
/// along the direction `dir` (unit), with `n` segments of length `h` on each side; the slave's
/// nodes shifted along the interface by `shift` and across it by `lift`.
fn interface(n: usize, h: f64, dir: Point, shift: f64, lift: f64) -> (Mesh, Mesh) {
    let normal = [-dir[1], dir[0]];
    let at = |s: f64, off: f64| [s * dir[0] + off * normal[0], s * dir[1] + off * normal[1]];
    let len = n as f64 * h;
    // Slave: the bottom runs along +dir (body on its left, i.e. above), closed over the top.
    let mut slave: Vec<Point> = (0..=n).map(|i| at(i as f64 * h + shift, lift)).collect();
    slave.push(at(len + shift, lift + 2.0 * h));
    slave.push(at(shift, lift + 2.0 * h));
    // Master: the top runs along −dir (body on its left, i.e. below), closed under it.
    let mut master: Vec<Point> = (0..=n).rev().map(|i| at(i as f64 * h, 0.0)).collect();
    master.push(at(0.0, -4.0 * h));
    master.push(at(len, -4.0 * h));
    (Mesh::boundary_loop(slave), Mesh::boundary_loop(master))
}

/// Candidate masks of the interface nodes (the first n + 1 of each loop).
fn interface_masks(slave: &Mesh, master: &Mesh, n: usize) -> (Vec<bool>, Vec<bool>) {
    let mask = |m: &Mesh| (0..m.nodes.len()).map(|i| i <= n).collect::<Vec<bool>>();
    (mask(slave), mask(master))
}

#[test]
fn degenerate_interfaces_match_the_scan() {
    let tol = 1e-9;
    let dirs: [(&str, Point); 4] = [
        ("horizontal", [1.0, 0.0]),
        ("vertical", [0.0, 1.0]),
        ("reversed", [-1.0, 0.0]),
        ("slanted", [0.6, 0.8]),
    ];
    for (name, dir) in dirs {
        for (what, shift, lift) in [
            // Coincident nodes: every slave node on a master node, two segments at distance 0.
            ("coincident", 0.0, 0.0),
            // Slave nodes exactly at the middle of master segments.
            ("mid-segment", 0.05, 0.0),
            // Within the tolerance of the segment ends (snapped to t ∈ {0, 1}).
            ("near ends", 0.5 * tol, 0.3 * tol),
            // A gap, and an overlap within and beyond the tolerance.
            ("gap", 0.03, 0.02),
            ("overlap", 0.03, -0.5 * tol),
            ("deep overlap", 0.03, -0.01),
        ] {
            let n = 200;
            let (slave, master) = interface(n, 0.1, dir, shift, lift);
            let (cand_s, cand_m) = interface_masks(&slave, &master, n);
            let case = format!("{name} {what}");
            for inside in [None, Some(0.0), Some(0.02)] {
                let inside_s = vec![inside; slave.nodes.len()];
                let built = same_rows(
                    &slave, &master, &cand_s, &cand_m, &inside_s, tol, 0.1, &case,
                );
                if inside.is_none() && lift >= 0.0 {
                    // An independent count: every interface node faces a master segment.
                    assert_eq!(built.rows.len() + built.unmatched, n + 1, "{case}");
                }
            }
            same_pipeline(&slave, &master, 0.1, tol, &case);
            same_pipeline(&master, &slave, 0.1, tol, &case);
        }
    }
}

#[test]
fn curved_masters_match_the_scan() {
    // A disc (master) under a ring arc (slave): non-conforming, slave nodes exactly on master
    // vertices at every third one, and a slave node at the disc's centre, equidistant from
    // every segment (the inside search's tie).
    for (k, tol) in [0.0, 1e-9, 1e-4].into_iter().enumerate() {
        let nm = 180 + 37 * k;
        let disc: Vec<Point> = (0..nm)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / nm as f64;
                [2.0 * a.cos(), 2.0 * a.sin()]
            })
            .collect();
        let master = Mesh::boundary_loop(disc.clone());
        // Slave: an arc above the disc, clockwise seen from the disc (body outside it), with
        // every third node a master vertex, the others on a circle of radius 2.001.
        let mut arc: Vec<Point> = (0..=nm / 2)
            .rev()
            .map(|i| {
                if i % 3 == 0 {
                    disc[i]
                } else {
                    let a = std::f64::consts::TAU * (i as f64 + 0.4) / nm as f64;
                    [2.001 * a.cos(), 2.001 * a.sin()]
                }
            })
            .collect();
        arc.push([-3.0, 3.0]);
        arc.push([3.0, 3.0]);
        let slave = Mesh::boundary_loop(arc);
        let case = format!("curved master, tol {tol}");
        let built = same_pipeline(&slave, &master, 0.05, tol, &case);
        assert!(!built.rows.is_empty(), "{case}");
        // The centre of the disc, inside: every segment at the same distance (up to rounding).
        let centre = Mesh::boundary_loop(vec![[0.0, 0.0], [0.01, 0.0], [0.0, 0.01]]);
        let cand = vec![true; 3];
        let inside = vec![Some(2.0); 3];
        let cand_m = vec![true; nm];
        let built = same_rows(&centre, &master, &cand, &cand_m, &inside, tol, 3.0, &case);
        assert_eq!(built.rows.len(), 3, "{case}: every inside node gets a row");
    }
}

#[test]
fn tolerance_chains_match_the_scan() {
    // Master segments stacked above one slave node at distances 1, 1 + 0.9 tol, 1 + 1.8 tol,
    // …, alternately interior and end projections, in scrambled list order: the running best
    // of the scan can move up the chain by tie-breaks, so a search that looked only at the
    // closest segment, or only within tol of it, would choose differently.
    let tol = 1e-3;
    let mut rng = Rng(42);
    for case in 0..50 {
        let layers = 2 + rng.below(12);
        let mut nodes: Vec<Point> = Vec::new();
        let mut segments: Vec<[usize; 2]> = Vec::new();
        for j in 0..layers {
            let y = 1.0 + 0.9 * tol * j as f64 + rng.range(0.0, 0.2 * tol);
            // Facing down (body above): a → b along +x.  Interior projection of x = 0, or
            // one starting exactly at x = 0.
            let (xa, xb) = if rng.unit() < 0.5 {
                (-rng.range(0.1, 1.0), rng.range(0.1, 1.0))
            } else {
                (0.0, rng.range(0.1, 1.0))
            };
            nodes.push([xa, y]);
            nodes.push([xb, y]);
            segments.push([nodes.len() - 2, nodes.len() - 1]);
        }
        // Scramble the list order.
        for i in (1..segments.len()).rev() {
            segments.swap(i, rng.below(i + 1));
        }
        let master = Mesh {
            nodes,
            cells: Cells::Triangles(Vec::new()),
            boundary: segments,
        };
        // The slave: a node at the origin on a top edge facing up.
        let slave = Mesh::boundary_loop(vec![[0.0, 0.0], [-0.5, -0.5], [0.5, -0.5]]);
        let slave = Mesh {
            boundary: vec![[1, 2], [2, 0], [0, 1]],
            ..slave
        };
        let cand_s = vec![true, false, false];
        let cand_m = vec![true; master.nodes.len()];
        for inside in [None, Some(1.5)] {
            let inside_s = vec![inside, None, None];
            let case = format!("chain {case}, inside {inside:?}");
            let built = same_rows(
                &slave, &master, &cand_s, &cand_m, &inside_s, tol, 2.0, &case,
            );
            assert_eq!(built.rows.len(), 1, "{case}");
        }
    }
}

#[test]
fn fixture_scenes_match_the_scan() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    let mut scenes = 0;
    for dir in ["seed", "hard"] {
        let mut paths: Vec<_> = std::fs::read_dir(root.join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
        paths.sort();
        for path in paths {
            let Ok(scene) = Scene::from_path(&path) else {
                continue;
            };
            let Ok(meshes) = crate::model::mesh_scene(&scene, &MeshLimits::default()) else {
                continue;
            };
            let fast = scene_rows(&scene, &meshes, Search::Indexed);
            let slow = scene_rows(&scene, &meshes, Search::BruteForce);
            let name = path.display().to_string();
            match (fast, slow) {
                (Ok(fast), Ok(slow)) => {
                    assert_eq!(fast.len(), slow.len(), "{name}");
                    for (f, s) in fast.iter().zip(&slow) {
                        let rows = |p: &PairRows| p.rows.iter().map(row_bits).collect::<Vec<_>>();
                        assert_eq!(rows(f), rows(s), "{name}");
                        // Everything else (counts, overlap) compared as a whole.
                        assert_eq!(format!("{f:?}"), format!("{s:?}"), "{name}");
                    }
                }
                (fast, slow) => {
                    assert_eq!(format!("{fast:?}"), format!("{slow:?}"), "{name}");
                }
            }
            scenes += 1;
        }
    }
    assert!(scenes >= 30, "only {scenes} fixture scenes read");
}

#[test]
fn long_interface_costs_a_bounded_number_of_evaluations_per_node() {
    // m = 20 001 slave nodes on a conforming straight interface of 20 000 master segments.
    // The scan evaluates every segment for every node (4·10⁸); the index a few per node.  The
    // bound 50 per node is the R-tree's: the nearest walk stops at the first admissible
    // segment (≤ 3 evaluated here), the box query returns the segments whose boxes meet the
    // node's neighbourhood (≤ 4 on a straight line), plus the final selection over those.
    let n = 20_000;
    let (slave, master) = interface(n, 0.01, [1.0, 0.0], 0.0, 0.0);
    let (cand_s, cand_m) = interface_masks(&slave, &master, n);
    let inside_s = vec![None; slave.nodes.len()];
    let segments = master_segments(&master, &cand_m, None, 1e-9);
    EVALUATIONS.with(|c| c.set(0));
    let built = pair_rows(
        &slave,
        &master,
        &cand_s,
        &segments,
        &inside_s,
        1e-9,
        0.01,
        Search::Indexed,
    );
    let evaluations = EVALUATIONS.with(Cell::get);
    assert_eq!(built.rows.len(), n + 1);
    assert!(
        evaluations <= 50 * (n + 1),
        "{evaluations} segment evaluations for {} nodes",
        n + 1
    );
    // Conforming: every row on a master node (t ∈ {0, 1}) with gap 0 and tributary h (h/2 at
    // the two ends), which the geometry gives independently of the search.
    for r in &built.rows {
        assert!(r.masters.iter().any(|&(_, w)| w == 1.0));
        assert_eq!(r.gap, 0.0);
        let end = r.slave_node == 0 || r.slave_node == n;
        let h = 0.01_f64;
        let expected = if end { 0.5 * h } else { h };
        // Tolerance: the edge lengths are differences of node abscissae up to 200, each rounded
        // to half an ulp (1.4e-14), so each half length is within 1.5e-14 of h/2: 1e-13 bounds
        // the sum of two.
        assert!((r.tributary - expected).abs() <= 1e-13, "{}", r.tributary);
    }
}

/// A strip (slave) on a foundation (master), both boundaries discretised all round with
/// segments of length `h`: `n` along the interface, 2 up the strip's ends, 4 down the
/// foundation's.
fn strip_on_foundation(n: usize, h: f64) -> (Mesh, Mesh) {
    let x = |i: usize| i as f64 * h;
    let y = |j: usize| j as f64 * h;
    let mut strip: Vec<Point> = (0..=n).map(|i| [x(i), 0.0]).collect();
    strip.push([x(n), y(1)]);
    strip.extend((0..=n).rev().map(|i| [x(i), y(2)]));
    strip.push([0.0, y(1)]);
    let mut foundation: Vec<Point> = (0..=n).rev().map(|i| [x(i), 0.0]).collect();
    foundation.extend((1..=3).map(|j| [0.0, -y(j)]));
    foundation.extend((0..=n).map(|i| [x(i), -y(4)]));
    foundation.extend((1..=3).rev().map(|j| [x(n), -y(j)]));
    (Mesh::boundary_loop(strip), Mesh::boundary_loop(foundation))
}

#[test]
fn a_region_box_over_whole_bodies_stays_cheap_and_matches_the_scan() {
    // Every boundary node a candidate (a region box covering both bodies): the strip's top
    // nodes face away from the foundation's top and lie in front of none of its bottom
    // segments, so they get no row.  The scan evaluates every segment for each of them; the
    // indexed search walks 32 segments outwards, then finds its cone (above the strip) empty.
    let n = 4000;
    let (strip, foundation) = strip_on_foundation(n, 0.01);
    for (slave, master, name) in [
        (&strip, &foundation, "strip slave"),
        (&foundation, &strip, "foundation slave"),
    ] {
        let cand_s = vec![true; slave.nodes.len()];
        let inside_s = vec![None; slave.nodes.len()];
        EVALUATIONS.with(|c| c.set(0));
        let built = pair_rows(
            slave,
            master,
            &cand_s,
            &master.boundary,
            &inside_s,
            1e-9,
            0.01,
            Search::Indexed,
        );
        let evaluations = EVALUATIONS.with(Cell::get);
        // The interface's n + 1 nodes get rows; the far side's nodes and the end nodes do not.
        assert_eq!(built.rows.len(), n + 1, "{name}");
        assert_eq!(
            built.rows.len() + built.unmatched,
            slave.nodes.len(),
            "{name}"
        );
        // WALK (32) evaluations for each unmatched node, a few for each matched one.
        assert!(
            evaluations <= 50 * slave.nodes.len(),
            "{name}: {evaluations} evaluations for {} nodes",
            slave.nodes.len()
        );
        let cand_m = vec![true; master.nodes.len()];
        same_rows(slave, master, &cand_s, &cand_m, &inside_s, 1e-9, 0.01, name);
    }
}

#[test]
fn a_node_slightly_behind_its_segment_is_found_past_the_walk() {
    // A slave node on the master's boundary (depth 0, so it may lie up to `limit` behind a
    // segment's line) whose only admissible segment lies 0.5 behind it, below 40 closer
    // decoys that do not face it: the search must go past its outward walk (32 segments) and
    // its cone must reach behind the node (apex pulled back by 1.5 (limit + tol)).
    let mut nodes: Vec<Point> = vec![[-1.0, -0.5], [1.0, -0.5]];
    let mut segments: Vec<[usize; 2]> = vec![[0, 1]];
    for k in 0..40 {
        let a = std::f64::consts::TAU * k as f64 / 40.0;
        let r = 0.1 + 0.3 * k as f64 / 40.0;
        let c = [r * a.cos(), r * a.sin()];
        // Along −x: outward normal +y, the same way as the slave's, so not facing it.
        nodes.push([c[0] + 0.01, c[1]]);
        nodes.push([c[0] - 0.01, c[1]]);
        segments.push([nodes.len() - 2, nodes.len() - 1]);
    }
    let master = Mesh {
        nodes,
        cells: Cells::Triangles(Vec::new()),
        boundary: segments,
    };
    let slave = Mesh {
        nodes: vec![[0.0, 0.0], [-0.5, -0.5], [0.5, -0.5]],
        cells: Cells::Triangles(Vec::new()),
        boundary: vec![[1, 2], [2, 0], [0, 1]],
    };
    let cand_s = vec![true, false, false];
    let cand_m = vec![true; master.nodes.len()];
    let inside_s = vec![Some(0.0), None, None];
    let built = same_rows(
        &slave, &master, &cand_s, &cand_m, &inside_s, 1e-9, 1.0, "behind",
    );
    // Independently: the row is on segment 0 at its middle (t = 1/2), gap −0.5.
    assert_eq!(built.rows.len(), 1);
    let row = &built.rows[0];
    assert_eq!(row.masters, vec![(0, 0.5), (1, 0.5)]);
    assert_eq!(row.gap, -0.5);
}

// ---------------------------------------------------------------------------------------------
// Node-to-segment geometry against hand computations: projections (t, gap, normal) on skew and
// curved masters, master corners, unmatched slave nodes, tributary lengths.  Every expected
// value below is derived from the geometry by a different route than the code's (rotations and
// trigonometry instead of dot products), and every case also runs through `same_rows`, so both
// searches must give it.
// ---------------------------------------------------------------------------------------------

/// The rows of a pair with every node outside the master (no depth), through both searches.
fn rows_outside(slave: &Mesh, master: &Mesh, cand_s: &[bool], cand_m: &[bool], tol: f64) -> Built {
    let inside_s = vec![None; slave.nodes.len()];
    same_rows(
        slave,
        master,
        cand_s,
        cand_m,
        &inside_s,
        tol,
        0.1,
        "hand-made",
    )
}

/// The weight a row puts on master node `k` (0 when it does not couple it).
fn weight_on(row: &ContactRow, k: usize) -> f64 {
    row.masters.iter().filter(|m| m.0 == k).map(|m| m.1).sum()
}

/// The row of slave node `x`, if any.
fn row_of(built: &Built, x: usize) -> Option<&ContactRow> {
    built.rows.iter().find(|r| r.slave_node == x)
}

/// A skew straight interface at angle `theta`: the master's top through the points at local
/// abscissae `xi_m` (line η = 0), the slave's bottom through (`xi_s`, `eta_s`), in the frame
/// rotated by θ.  Returns the meshes (interface nodes first, in the order given) and the map
/// from local to global coordinates.
fn skew_interface(
    theta: f64,
    xi_m: &[f64],
    xi_s: &[f64],
    eta_s: &[f64],
) -> (Mesh, Mesh, impl Fn(f64, f64) -> Point) {
    let (c, s) = (theta.cos(), theta.sin());
    let at = move |xi: f64, eta: f64| [c * xi - s * eta, s * xi + c * eta];
    // Slave bottom along +ξ (body above, on the left), closed over the top.
    let mut slave: Vec<Point> = xi_s.iter().zip(eta_s).map(|(&x, &e)| at(x, e)).collect();
    let (first, last) = (xi_s[0], xi_s[xi_s.len() - 1]);
    slave.push(at(last, 1.0));
    slave.push(at(first, 1.0));
    // Master top along −ξ (body below, on the left): listed in decreasing ξ, closed underneath.
    let mut master: Vec<Point> = xi_m.iter().rev().map(|&x| at(x, 0.0)).collect();
    let (lo, hi) = (xi_m[0], xi_m[xi_m.len() - 1]);
    master.push(at(lo, -1.0));
    master.push(at(hi, -1.0));
    (Mesh::boundary_loop(slave), Mesh::boundary_loop(master), at)
}

#[test]
fn projections_on_a_skew_master_give_t_gap_and_normal_of_the_rotated_frame() {
    // θ = 0.5 rad; master nodes unevenly spaced, slave nodes between them at heights η ≥ 0.
    // In the frame rotated by θ the master top is the line η = 0: a slave node (ξ, η) over the
    // master segment [ξ_lo, ξ_hi] projects at ξ, with weights (ξ_hi − ξ)/(ξ_hi − ξ_lo) on the
    // node at ξ_lo and (ξ − ξ_lo)/(ξ_hi − ξ_lo) on the one at ξ_hi, gap η and normal the
    // rotated (0, 1) = (−sin θ, cos θ).
    let theta: f64 = 0.5;
    let xi_m = [0.0, 0.37, 0.81, 1.3, 1.72, 2.2];
    let xi_s = [0.1, 0.55, 1.0, 1.5, 2.05];
    let eta_s = [0.01, 0.0, 0.02, 0.005, 0.0];
    let (slave, master, _) = skew_interface(theta, &xi_m, &xi_s, &eta_s);
    let cand_s: Vec<bool> = (0..slave.nodes.len()).map(|i| i < xi_s.len()).collect();
    let cand_m: Vec<bool> = (0..master.nodes.len()).map(|i| i < xi_m.len()).collect();
    let tol = 1e-9;
    let built = rows_outside(&slave, &master, &cand_s, &cand_m, tol);
    assert_eq!((built.rows.len(), built.unmatched), (xi_s.len(), 0));
    // Master node of abscissa xi_m[k] has index (n − 1 − k) (listed in decreasing ξ).
    let node = |k: usize| xi_m.len() - 1 - k;
    // Tolerance: coordinates of order 2 rotated and projected back carry a few ulps (1e-15);
    // divided by a segment length ≥ 0.37 they stay below 1e-14 in t; gaps within the snapping
    // tolerance (1e-9) of 0 are written as 0.
    for (i, (&xi, &eta)) in xi_s.iter().zip(&eta_s).enumerate() {
        let row = row_of(&built, i).expect("every slave node faces the master");
        let k = xi_m
            .windows(2)
            .position(|w| w[0] < xi && xi < w[1])
            .unwrap();
        let (lo, hi) = (xi_m[k], xi_m[k + 1]);
        let w_lo = (hi - xi) / (hi - lo);
        assert!(
            (weight_on(row, node(k)) - w_lo).abs() < 1e-14,
            "node {i}: {row:?}"
        );
        assert!(
            (weight_on(row, node(k + 1)) - (1.0 - w_lo)).abs() < 1e-14,
            "node {i}"
        );
        assert_eq!(row.masters.len(), 2);
        assert!(
            (row.gap - eta).abs() < 1e-14 || (eta == 0.0 && row.gap == 0.0),
            "{i}"
        );
        assert!(
            (row.normal[0] + theta.sin()).abs() < 1e-15,
            "{:?}",
            row.normal
        );
        assert!(
            (row.normal[1] - theta.cos()).abs() < 1e-15,
            "{:?}",
            row.normal
        );
        assert_eq!(row.position, slave.nodes[i]);
    }
}

/// A regular polygon of `n` vertices on the circle of radius `r` about the origin, counter-
/// clockwise from angle 0 (a disc's boundary, body inside).
fn disc(n: usize, r: f64) -> Vec<Point> {
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            [r * a.cos(), r * a.sin()]
        })
        .collect()
}

/// A slave cap over a disc: its inner boundary through the points (ρᵢ, φᵢ) in polar
/// coordinates, listed by decreasing angle (clockwise, so the cap lies outside the disc on the
/// left), closed far above.
fn cap(polar: &[(f64, f64)]) -> Mesh {
    let mut pts: Vec<Point> = polar
        .iter()
        .map(|&(rho, phi)| [rho * phi.cos(), rho * phi.sin()])
        .collect();
    pts.push([-5.0, 5.0]);
    pts.push([5.0, 5.0]);
    Mesh::boundary_loop(pts)
}

#[test]
fn projections_on_a_curved_master_follow_the_chords_trigonometry() {
    // Master: a 24-gon of radius R = 2 (chords of Δ = 15°).  A slave node at polar (ρ, φ) over
    // the chord from vertex k (angle φ_k) to vertex k + 1, of mid-angle φ_m = φ_k + Δ/2: in the
    // chord's frame it lies ρ sin(φ − φ_m) along the chord from its midpoint and
    // ρ cos(φ − φ_m) − R cos(Δ/2) above its line, so t = 1/2 + ρ sin(φ − φ_m) / (2 R sin(Δ/2))
    // (from vertex k, the boundary runs counter-clockwise) and gap = ρ cos(φ − φ_m) − R cos(Δ/2);
    // the normal is (cos φ_m, sin φ_m).  The slave nodes sit at fractions of their chord's
    // angle that keep the projection inside it, at gaps from 0 to 0.01: non-matching.
    let (n, r) = (24, 2.0);
    let delta = std::f64::consts::TAU / n as f64;
    let master = Mesh::boundary_loop(disc(n, r));
    // (chord k, fraction of Δ from vertex k, radius ρ), listed clockwise.
    let nodes = [
        (9usize, 0.7, 2.0),
        (8, 0.5, 2.004),
        (7, 0.2, 2.01),
        (6, 0.45, 1.995),
        (5, 0.8, 2.0),
        (4, 0.35, 2.002),
        (3, 0.6, 2.0),
    ];
    let polar: Vec<(f64, f64)> = nodes
        .iter()
        .map(|&(k, f, rho)| (rho, (k as f64 + f) * delta))
        .collect();
    let slave = cap(&polar);
    let cand_s: Vec<bool> = (0..slave.nodes.len()).map(|i| i < nodes.len()).collect();
    let cand_m = vec![true; n];
    let built = rows_outside(&slave, &master, &cand_s, &cand_m, 1e-9);
    assert_eq!((built.rows.len(), built.unmatched), (nodes.len(), 0));
    for (i, &(k, f, rho)) in nodes.iter().enumerate() {
        let row = row_of(&built, i).unwrap();
        let phi = (k as f64 + f) * delta;
        let phi_m = (k as f64 + 0.5) * delta;
        let t = 0.5 + rho * (phi - phi_m).sin() / (2.0 * r * (0.5 * delta).sin());
        let gap = rho * (phi - phi_m).cos() - r * (0.5 * delta).cos();
        // Tolerance: trigonometric values and coordinates of order 2 differ from the code's
        // dot products by a few ulps (1e-15), divided by a chord of 0.52: 1e-14.
        assert!(
            (weight_on(row, k) - (1.0 - t)).abs() < 1e-14,
            "node {i}: {row:?}"
        );
        assert!(
            (weight_on(row, (k + 1) % n) - t).abs() < 1e-14,
            "node {i}: {row:?}"
        );
        assert!(
            (row.gap - gap).abs() < 1e-14,
            "node {i}: {} vs {gap}",
            row.gap
        );
        assert!((row.normal[0] - phi_m.cos()).abs() < 1e-15, "node {i}");
        assert!((row.normal[1] - phi_m.sin()).abs() < 1e-15, "node {i}");
    }
    // Node 3 (ρ = 1.995) lies inside the circle of radius 2 but outside the polygon: its gap
    // to the chord is positive (R cos(Δ/2) = 1.983), as the polygonal master demands.
    assert!(row_of(&built, 3).unwrap().gap > 0.01);
}

#[test]
fn a_slave_node_on_a_master_vertex_of_a_curved_master_couples_that_vertex_alone() {
    // Conforming: slave nodes on the vertices 3..=9 of the 24-gon.  Each projects on a vertex
    // (t ∈ {0, 1} on one of its two chords) with gap 0 and weight 1 on that vertex; the normal
    // is one of the two chords' normals, at angle (k ± 1/2) Δ.
    let (n, r) = (24, 2.0);
    let delta = std::f64::consts::TAU / n as f64;
    let vertices = disc(n, r);
    let master = Mesh::boundary_loop(vertices.clone());
    let ks: Vec<usize> = (3..=9).rev().collect();
    let mut pts: Vec<Point> = ks.iter().map(|&k| vertices[k]).collect();
    pts.push([-5.0, 5.0]);
    pts.push([5.0, 5.0]);
    let slave = Mesh::boundary_loop(pts);
    let cand_s: Vec<bool> = (0..slave.nodes.len()).map(|i| i < ks.len()).collect();
    let built = rows_outside(&slave, &master, &cand_s, &vec![true; n], 1e-9);
    assert_eq!(built.rows.len(), ks.len());
    for (i, &k) in ks.iter().enumerate() {
        let row = row_of(&built, i).unwrap();
        assert_eq!(weight_on(row, k), 1.0, "{row:?}");
        assert_eq!(row.gap, 0.0);
        let angle = row.normal[1].atan2(row.normal[0]);
        let near = |a: f64| (angle - a).abs() < 1e-14;
        assert!(
            near((k as f64 - 0.5) * delta) || near((k as f64 + 0.5) * delta),
            "vertex {k}: normal at {angle}"
        );
    }
}

/// An L-shaped master: [0, 2] × [0, 1] ∪ [0, 1] × [1, 2], counter-clockwise from the origin.
/// Its convex corners include (2, 1); its re-entrant corner is (1, 1) = node 3, between edge
/// [2, 3] ((2, 1) → (1, 1), outward normal (0, 1)) and edge [3, 4] ((1, 1) → (1, 2), outward
/// normal (1, 0)).
fn l_master() -> Mesh {
    Mesh::boundary_loop(vec![
        [0.0, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [1.0, 1.0],
        [1.0, 2.0],
        [0.0, 2.0],
    ])
}

/// A slave triangle with its apex X (node 0) pointing along `towards` (unit), so that the
/// slave's outward normal at X (the sum of its two edges' normals) is `towards`.
fn slave_apex(x: Point, towards: Point) -> Mesh {
    let back = [x[0] - 0.1 * towards[0], x[1] - 0.1 * towards[1]];
    let side = [-towards[1], towards[0]];
    let p = [back[0] + 0.1 * side[0], back[1] + 0.1 * side[1]];
    let q = [back[0] - 0.1 * side[0], back[1] - 0.1 * side[1]];
    // Counter-clockwise: X, then the left back corner, then the right one (as seen looking along
    // `towards`).
    let mesh = Mesh::boundary_loop(vec![x, p, q]);
    let area = crate::geometry::orient(mesh.nodes[0], mesh.nodes[1], mesh.nodes[2]);
    if area > 0.0 {
        mesh
    } else {
        Mesh::boundary_loop(vec![x, q, p])
    }
}

#[test]
fn at_master_corners_the_row_takes_the_segment_the_hand_derivation_gives() {
    let master = l_master();
    let cand_m = vec![true; master.nodes.len()];
    let cand_s = [true, false, false];
    let tol = 1e-9;
    let s2 = std::f64::consts::FRAC_1_SQRT_2;
    let down_left = [-s2, -s2];
    let case = |x: Point, towards: Point| {
        let slave = slave_apex(x, towards);
        rows_outside(&slave, &master, &cand_s, &cand_m, tol)
    };

    // 1. Convex corner (2, 1) = node 2, a slave node above it at (2, 1.2) facing down: the top
    //    edge [2, 3] faces it (normals opposite) and its projection is the corner itself
    //    (t = 0 from node 2), gap 0.2; the right edge [1, 2] (normal (1, 0)) is perpendicular
    //    to the slave's normal, cos = 0 > −0.3: not facing.  Row: edge [2, 3], normal (0, 1),
    //    weight 1 on node 2, gap 0.2.
    let b = case([2.0, 1.2], [0.0, -1.0]);
    let row = &b.rows[0];
    assert_eq!(weight_on(row, 2), 1.0, "{row:?}");
    assert_eq!(row.normal, [0.0, 1.0]);
    assert!((row.gap - 0.2).abs() < 1e-15, "{}", row.gap); // 1.2 − 1 rounded once
                                                           // 2. The same corner seen diagonally from (2.1, 1.1), slave normal (−1, −1)/√2: both edges
                                                           //    at the corner face it (cos = −1/√2), but its projection on the top edge's line is at
                                                           //    x = 2.1, beyond the segment [1, 2] by 0.1 ≫ tol, and on the right edge's line at
                                                           //    y = 1.1, beyond [0, 1]: the node lies in the corner's exterior wedge, where no segment
                                                           //    projection exists: no row, counted unmatched.
                                                           //    That holds when the corner's two edges are the only master candidates (a region box
                                                           //    around the corner: nodes 1, 2, 3).
    let corner_only = [false, true, true, true, false, false];
    let slave = slave_apex([2.1, 1.1], down_left);
    let b = rows_outside(&slave, &master, &cand_s, &corner_only, tol);
    assert_eq!((b.rows.len(), b.unmatched), (0, 1));
    //    With the whole L a candidate, the wall [3, 4] (x = 1, y ∈ [1, 2], normal (1, 0)) also
    //    faces the node, across the open space above the lower part, and contains its
    //    projection y = 1.1: row there, gap 2.1 − 1 = 1.1, t = 0.1 from node 3.
    let b = case([2.1, 1.1], down_left);
    let row = &b.rows[0];
    assert_eq!(row.normal, [1.0, 0.0]);
    assert!((weight_on(row, 3) - 0.9).abs() < 1e-15, "{row:?}"); // 1.1 − 1 rounded once
    assert!((weight_on(row, 4) - 0.1).abs() < 1e-15, "{row:?}");
    assert!((row.gap - 1.1).abs() < 1e-15, "{}", row.gap);
    // 3. Within the tolerance of the wedge's edge: from (2 + 1e-10, 1.3) the top edge's
    //    projection is 1e-10 beyond its end (< tol, snapped to t = 0 at node 2): row on the top
    //    edge, normal (0, 1), gap 0.3, weight 1 on node 2.
    let b = case([2.0 + 1e-10, 1.3], down_left);
    let row = &b.rows[0];
    assert_eq!((weight_on(row, 2), row.normal), (1.0, [0.0, 1.0]));
    assert!((row.gap - 0.3).abs() < 1e-15, "{}", row.gap);
    // 4. Re-entrant corner (1, 1) = node 3, from (1.3, 1.1) facing down-left: the top edge
    //    [2, 3] (projection x = 1.3, t = 0.7 from node 2, distance 0.1) and the right edge
    //    [3, 4] (projection y = 1.1, distance 0.3) both face it; the closer wins: normal (0, 1),
    //    weights 0.3 on node 2 and 0.7 on node 3, gap 0.1.
    let b = case([1.3, 1.1], down_left);
    let row = &b.rows[0];
    assert_eq!(row.normal, [0.0, 1.0]);
    // t = (2 − 1.3) / 1 in floating point: 1e-15.
    assert!((weight_on(row, 2) - 0.3).abs() < 1e-15, "{row:?}");
    assert!((weight_on(row, 3) - 0.7).abs() < 1e-15, "{row:?}");
    assert!((row.gap - 0.1).abs() < 1e-15, "{}", row.gap);
    // 5. The same corner from (1.1, 1.3): now the right edge is closer (0.1 against 0.3):
    //    normal (1, 0), t = 0.3 from node 3 (weights 0.7 on node 3, 0.3 on node 4), gap 0.1.
    let b = case([1.1, 1.3], down_left);
    let row = &b.rows[0];
    assert_eq!(row.normal, [1.0, 0.0]);
    assert!((weight_on(row, 3) - 0.7).abs() < 1e-15, "{row:?}");
    assert!((weight_on(row, 4) - 0.3).abs() < 1e-15, "{row:?}");
    assert!((row.gap - 0.1).abs() < 1e-15, "{}", row.gap);
    // 6. On the bisector, (1.25, 1.25): both edges at distance 0.25 (the same float), both
    //    projections interior, both facing: a tie that no rule breaks, so the segment met first
    //    in the boundary's order stays, edge [2, 3] (listed before [3, 4]): normal (0, 1),
    //    t = (2 − 1.25) / 1 = 0.75 from node 2, so weights 0.25 on node 2 and 0.75 on node 3
    //    (all exact in binary).
    let b = case([1.25, 1.25], down_left);
    let row = &b.rows[0];
    assert_eq!(row.normal, [0.0, 1.0]);
    assert_eq!((weight_on(row, 2), weight_on(row, 3)), (0.25, 0.75));
    assert_eq!(row.gap, 0.25);
}

#[test]
fn slave_nodes_without_a_facing_master_segment_are_counted_never_dropped() {
    // A slave bottom over [−1, 3] (nodes every 0.25) on a master top over [0, 2]: the slave
    // nodes beyond the master's span (x < 0 or x > 2, by more than tol) face no segment within
    // its span.  Every candidate either has a row or is counted in `unmatched`.
    let xs: Vec<f64> = (0..=16).map(|i| -1.0 + 0.25 * f64::from(i)).collect();
    let mut slave: Vec<Point> = xs.iter().map(|&x| [x, 0.01]).collect();
    slave.push([3.0, 1.0]);
    slave.push([-1.0, 1.0]);
    let slave = Mesh::boundary_loop(slave);
    let master = Mesh::boundary_loop(vec![
        [2.0, 0.0],
        [1.0, 0.0],
        [0.0, 0.0],
        [0.0, -1.0],
        [2.0, -1.0],
    ]);
    let cand_s: Vec<bool> = (0..slave.nodes.len()).map(|i| i < xs.len()).collect();
    let cand_m = vec![true, true, true, false, false];
    let built = rows_outside(&slave, &master, &cand_s, &cand_m, 1e-9);
    let inside_span = xs.iter().filter(|&&x| (0.0..=2.0).contains(&x)).count();
    assert_eq!(inside_span, 9);
    assert_eq!(built.rows.len(), inside_span);
    assert_eq!(built.unmatched, xs.len() - inside_span);
    for r in &built.rows {
        assert!((0.0..=2.0).contains(&r.position[0]), "{r:?}");
    }

    // The slave's two top corners made candidates too: their outward normal, (±1, 1) summed
    // over their two edges, makes cos = 1/√2 > −0.3 with the master top's (0, 1): not facing,
    // so two more unmatched.
    let cand_s = vec![true; slave.nodes.len()];
    let built = rows_outside(&slave, &master, &cand_s, &cand_m, 1e-9);
    assert_eq!(built.rows.len() + built.unmatched, slave.nodes.len());
    assert_eq!(built.unmatched, xs.len() - inside_span + 2);

    // Through the whole pipeline (`contact_rows`): an overhanging block on a shorter one, every
    // candidate counted: candidates = rows + unmatched, and the unmatched ones are exactly the
    // slave boundary nodes in the region with x outside the master's [0, 2].
    let scene = Scene::from_toml(
        r#"
title = "overhang"
[[body]]
name = "top"
polygon = [[-1, 0], [3, 0], [3, 1], [-1, 1]]
hmax = 0.25
young = 1.0
poisson = 0.3
[[body]]
name = "bottom"
polygon = [[0, -1], [2, -1], [2, 0], [0, 0]]
hmax = 0.3
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "bottom"
region = [0, 2, -1, -1]
[[contact]]
bodies = ["top", "bottom"]
slave = "top"
region = [-1, 3, -0.01, 0.01]
"#,
    )
    .unwrap();
    let meshes = crate::model::mesh_scene(&scene, &MeshLimits::default()).unwrap();
    let pairs = scene_rows(&scene, &meshes, Search::Indexed).unwrap();
    let p = &pairs[0];
    assert_eq!(p.slave, 0);
    assert_eq!(p.candidates, p.rows.len() + p.unmatched);
    let on = boundary_node_mask(&meshes[0]);
    let tol = scene.tolerance();
    let beyond = meshes[0]
        .nodes
        .iter()
        .enumerate()
        .filter(|&(i, q)| on[i] && q[1].abs() <= 0.01 + tol && (q[0] < -tol || q[0] > 2.0 + tol))
        .count();
    assert!(beyond >= 8, "the overhang has nodes ({beyond})");
    assert_eq!(p.unmatched, beyond);
}

/// Σ tributary of a pair's rows.
fn tributary_sum(built: &Built) -> f64 {
    built.rows.iter().map(|r| r.tributary).sum()
}

#[test]
fn tributary_lengths_sum_to_the_slave_interface_length_on_straight_interfaces() {
    // Skew straight interfaces of length 2.05 − 0.1 = 1.95 (slave nodes at the ξ below, η = 0
    // or small): each node gets half of each adjacent interface edge, so the sum is the chain's
    // length, Σ |ξᵢ₊₁ − ξᵢ| when η = 0.  Conforming (slave nodes on master nodes) and non-matching.
    let theta = 0.3;
    let xi_s = [0.1, 0.55, 1.0, 1.5, 2.05];
    let flat = [0.0; 5];
    // Non-matching: master nodes elsewhere, covering the slave's span.
    let (slave, master, _) =
        skew_interface(theta, &[0.0, 0.37, 0.81, 1.3, 1.72, 2.2], &xi_s, &flat);
    let cand_s: Vec<bool> = (0..slave.nodes.len()).map(|i| i < 5).collect();
    let cand_m: Vec<bool> = (0..master.nodes.len()).map(|i| i < 6).collect();
    let built = rows_outside(&slave, &master, &cand_s, &cand_m, 1e-9);
    assert_eq!(built.rows.len(), 5);
    assert_eq!(built.tributary_fallbacks, 0);
    // Rounding: five rotated coordinates of order 2, a few ulps each: 1e-14.
    assert!(
        (tributary_sum(&built) - 1.95).abs() < 1e-14,
        "{}",
        tributary_sum(&built)
    );
    // Conforming: the master nodes are the slave's.
    let (slave, master, _) = skew_interface(theta, &xi_s, &xi_s, &flat);
    let cand_m: Vec<bool> = (0..master.nodes.len()).map(|i| i < 5).collect();
    let built = rows_outside(&slave, &master, &cand_s, &cand_m, 1e-9);
    assert_eq!(built.rows.len(), 5);
    assert!(built.rows.iter().all(|r| r.gap == 0.0));
    assert!(
        (tributary_sum(&built) - 1.95).abs() < 1e-14,
        "{}",
        tributary_sum(&built)
    );
    // A wavy slave (η ≠ 0): the chain's length is Σ √(Δξ² + Δη²).
    let eta = [0.01, 0.0, 0.02, 0.005, 0.0];
    let (slave, master, _) = skew_interface(theta, &[0.0, 0.37, 0.81, 1.3, 1.72, 2.2], &xi_s, &eta);
    let cand_m: Vec<bool> = (0..master.nodes.len()).map(|i| i < 6).collect();
    let built = rows_outside(&slave, &master, &cand_s, &cand_m, 1e-9);
    let length: f64 = (0..4)
        .map(|i| (xi_s[i + 1] - xi_s[i]).hypot(eta[i + 1] - eta[i]))
        .sum();
    assert!((tributary_sum(&built) - length).abs() < 1e-14);
}

#[test]
fn tributary_lengths_sum_to_the_slave_interface_length_on_curved_interfaces() {
    let (n, r) = (24, 2.0);
    let delta = std::f64::consts::TAU / n as f64;
    let master = Mesh::boundary_loop(disc(n, r));
    let cand_m = vec![true; n];
    // Conforming: slave nodes on vertices 3..=9, six chords of 2 R sin(Δ/2).
    let polar: Vec<(f64, f64)> = (3..=9).rev().map(|k| (r, k as f64 * delta)).collect();
    let slave = cap(&polar);
    let cand_s: Vec<bool> = (0..slave.nodes.len()).map(|i| i < polar.len()).collect();
    let built = rows_outside(&slave, &master, &cand_s, &cand_m, 1e-9);
    assert_eq!(built.rows.len(), 7);
    let want = 6.0 * 2.0 * r * (0.5 * delta).sin();
    // Rounding of seven coordinates from cos/sin (1 ulp each) over six lengths: 1e-14.
    assert!(
        (tributary_sum(&built) - want).abs() < 1e-14,
        "{}",
        tributary_sum(&built)
    );
    // Non-matching: ten slave nodes on the circle of radius R at angles between the vertices
    // (every 0.7 Δ from 3.2 Δ): nine chords of 2 R sin(0.35 Δ).
    let polar: Vec<(f64, f64)> = (0..10)
        .rev()
        .map(|i| (r, (3.2 + 0.7 * f64::from(i)) * delta))
        .collect();
    let slave = cap(&polar);
    let cand_s: Vec<bool> = (0..slave.nodes.len()).map(|i| i < polar.len()).collect();
    let built = rows_outside(&slave, &master, &cand_s, &cand_m, 1e-9);
    assert_eq!((built.rows.len(), built.unmatched), (10, 0));
    assert_eq!(built.tributary_fallbacks, 0);
    let want = 9.0 * 2.0 * r * (0.35 * delta).sin();
    assert!(
        (tributary_sum(&built) - want).abs() < 1e-14,
        "{}",
        tributary_sum(&built)
    );
}

#[test]
fn tributary_lengths_sum_to_the_interface_length_on_meshed_fixtures() {
    // Experiments 2b (conforming, hmax 0.2 both) and 3 (non-matching: lower body at 0.15,
    // 0.1, 0.08): the slave is the upper body, its interface y = 1, x ∈ [1, 2], length 1 by
    // the scene's polygons; every interface node gets a row.  Rounding: ≤ 50 half-lengths of
    // order 0.1 (1e-16 each): 1e-14.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/seed");
    for name in [
        "exp2b.toml",
        "exp3-body2-h0.15.toml",
        "exp3-body2-h0.1.toml",
        "exp3-body2-h0.08.toml",
        "exp3-both-h0.08.toml",
    ] {
        let scene = Scene::from_path(&root.join(name)).unwrap();
        let meshes = crate::model::mesh_scene(&scene, &MeshLimits::default()).unwrap();
        let pairs = scene_rows(&scene, &meshes, Search::Indexed).unwrap();
        let p = &pairs[0];
        assert_eq!((p.unmatched, p.tributary_fallbacks), (0, 0), "{name}");
        let sum: f64 = p.rows.iter().map(|r| r.tributary).sum();
        assert!((sum - 1.0).abs() < 1e-14, "{name}: Σ tributary = {sum}");
    }
}

#[test]
fn a_region_box_that_cuts_a_master_edge_keeps_that_edge() {
    // A coarse base (top nodes at x = 0, 1, 2) under a fine block (bottom nodes every 0.1), the
    // contact box ending at x = 1.5, between two base nodes (a Gmsh master: the polygon mesher
    // puts a node where a box crosses an edge).  With only edges whose both ends lie in the box
    // as master segments, the block's bottom nodes in (1, 1.5] faced no segment, got no row and
    // could sink into the base (the fuzz replay
    // unmatched-slave-corner-inside-master-where-region-cuts-master-segment).  The edge from 1
    // to 2 crosses the box: every candidate gets a row, in both formulations.
    let master = Mesh::boundary_loop(vec![
        [0.0, -1.0],
        [2.0, -1.0],
        [2.0, 0.0],
        [1.0, 0.0],
        [0.0, 0.0],
    ]);
    let mut block: Vec<Point> = (0..=20).map(|i| [0.1 * i as f64, 0.0]).collect();
    block.extend([[2.0, 1.0], [0.0, 1.0]]);
    let slave = Mesh::boundary_loop(block);
    let (region, tol) = ([0.0, 1.5, -0.01, 0.01], 1e-9);
    let in_box = |m: &Mesh| -> Vec<bool> {
        m.nodes
            .iter()
            .map(|&p| geometry::in_box(p, &region, tol))
            .collect()
    };
    let (cand_s, cand_m) = (in_box(&slave), in_box(&master));
    assert_eq!(cand_s.iter().filter(|c| **c).count(), 16);
    let inside_s = vec![None; slave.nodes.len()];
    let old = master_segments(&master, &cand_m, None, tol);
    let built = pair_rows(
        &slave,
        &master,
        &cand_s,
        &old,
        &inside_s,
        tol,
        0.5,
        Search::Indexed,
    );
    assert_eq!((built.rows.len(), built.unmatched), (11, 5));
    let segments = master_segments(&master, &cand_m, Some(&region), tol);
    // The top's two edges and the base's left side (it crosses the box at x = 0; it faces no
    // slave node, so no row takes it).
    assert_eq!(segments, vec![[2, 3], [3, 4], [4, 0]]);
    let built = pair_rows(
        &slave,
        &master,
        &cand_s,
        &segments,
        &inside_s,
        tol,
        0.5,
        Search::Indexed,
    );
    assert_eq!((built.rows.len(), built.unmatched), (16, 0));
    let mortar = mortar::pair_rows(
        &slave,
        &master,
        &cand_s,
        &segments,
        &inside_s,
        tol,
        0.5,
        mortar::Frame::Master,
    );
    assert_eq!((mortar.rows.len(), mortar.unmatched), (16, 0));
}
