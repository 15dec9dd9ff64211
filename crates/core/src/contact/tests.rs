//! The indexed contact search against the brute-force scan it replaced ([`Search::BruteForce`],
//! kept as a test-only oracle): bit-identical rows, in the same order, with the same gaps,
//! weights, normals and tributary lengths, on random and on degenerate geometries and on every
//! fixture scene; and the indexed search's cost per node on a long interface.
//!
//! No tolerance appears in the comparisons: results are compared bit for bit (`f64::to_bits`).

#![allow(clippy::unwrap_used, clippy::expect_used)] // tests may unwrap

use std::cell::Cell;

use super::*;
use crate::mesh::{Cells, Mesh, MeshLimits};

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

/// A boundary-only mesh: the closed loop `points` (counter-clockwise for a body on the left).
fn loop_mesh(points: Vec<Point>) -> Mesh {
    let n = points.len();
    Mesh {
        nodes: points,
        cells: Cells::Triangles(Vec::new()),
        boundary: (0..n).map(|i| [i, (i + 1) % n]).collect(),
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
    let fast = pair_rows(
        slave,
        master,
        cand_s,
        cand_m,
        inside_s,
        tol,
        limit,
        Search::Indexed,
    );
    let slow = pair_rows(
        slave,
        master,
        cand_s,
        cand_m,
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
        let slave = loop_mesh(star(&mut rng, [0.0, 0.0], 4.0, ns, snap));
        // Separated, touching or overlapping: the master's centre 0 to 10 away.
        let offset = [rng.range(-10.0, 10.0), rng.range(-10.0, 10.0)];
        let master = loop_mesh(star(&mut rng, offset, 4.0, nm, snap));
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
    (loop_mesh(slave), loop_mesh(master))
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
        let master = loop_mesh(disc.clone());
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
        let slave = loop_mesh(arc);
        let case = format!("curved master, tol {tol}");
        let built = same_pipeline(&slave, &master, 0.05, tol, &case);
        assert!(!built.rows.is_empty(), "{case}");
        // The centre of the disc, inside: every segment at the same distance (up to rounding).
        let centre = loop_mesh(vec![[0.0, 0.0], [0.01, 0.0], [0.0, 0.01]]);
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
        let slave = loop_mesh(vec![[0.0, 0.0], [-0.5, -0.5], [0.5, -0.5]]);
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
            let fast = contact_rows_with(&scene, &meshes, Search::Indexed);
            let slow = contact_rows_with(&scene, &meshes, Search::BruteForce);
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
    EVALUATIONS.with(|c| c.set(0));
    let built = pair_rows(
        &slave,
        &master,
        &cand_s,
        &cand_m,
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
    (loop_mesh(strip), loop_mesh(foundation))
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
        let cand_m = vec![true; master.nodes.len()];
        let inside_s = vec![None; slave.nodes.len()];
        EVALUATIONS.with(|c| c.set(0));
        let built = pair_rows(
            slave,
            master,
            &cand_s,
            &cand_m,
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
