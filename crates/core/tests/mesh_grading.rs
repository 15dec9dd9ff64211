//! Graded meshes (`[[body.refine]]`): the size function is followed (edges ≤ h(x), ≤ the region's
//! hmax inside its box), sizes change gradually, angles and area hold, interfaces conform, the
//! element count and its estimate, graded Q1 grids, and meshes without regions unchanged.
//!
//! The size function is re-implemented here from its documented formula
//! h(x) = min(hmax, min_r (h_r + 0.25 · dist(x, box_r))), independently of `mesh/sizing.rs`.

#![allow(clippy::unwrap_used)] // tests may unwrap (helpers included)

use std::collections::HashMap;
use std::time::Instant;

use signorini_core::geometry::{bounding_box, distance, signed_area, Point};
use signorini_core::mesh::{
    estimate_elements, estimate_elements_refined, estimate_nodes_refined, mesh_body, BodyGeometry,
    Cells, ElementKind, Mesh, MeshLimits, Refinement, GRADING,
};
use signorini_core::model::mesh_scene;
use signorini_core::scene::Scene;

/// The Hertz-like block of the issue: 0.8 × 0.4, hmax 0.05, refined to 0.0025 near the top
/// middle.
const BLOCK: [Point; 4] = [[0.0, 0.0], [0.8, 0.0], [0.8, 0.4], [0.0, 0.4]];
const BLOCK_HMAX: f64 = 0.05;
const HERTZ: Refinement = Refinement {
    region: [0.35, 0.45, 0.38, 0.4],
    hmax: 0.0025,
};

fn size(p: Point, hmax: f64, refine: &[Refinement]) -> f64 {
    refine
        .iter()
        .map(|r| {
            let dx = (r.region[0] - p[0]).max(p[0] - r.region[1]).max(0.0);
            let dy = (r.region[2] - p[1]).max(p[1] - r.region[3]).max(0.0);
            r.hmax + (GRADING - 1.0) * dx.hypot(dy)
        })
        .fold(hmax, f64::min)
}

fn geometry<'a>(
    polygon: &'a [Point],
    hmax: f64,
    element: ElementKind,
    breakpoints: &'a [Point],
    refine: &'a [Refinement],
) -> BodyGeometry<'a> {
    BodyGeometry {
        polygon,
        hmax,
        element,
        breakpoints,
        refine,
        tol: 1e-9,
    }
}

fn hertz_mesh(element: ElementKind) -> Mesh {
    // The box's crossings with the top edge, as `mesh_scene` passes them.
    let breaks = [[0.35, 0.4], [0.45, 0.4]];
    mesh_body(
        &geometry(&BLOCK, BLOCK_HMAX, element, &breaks, &[HERTZ]),
        &MeshLimits::default(),
    )
    .unwrap()
}

fn edges(mesh: &Mesh) -> Vec<(Point, Point)> {
    (0..mesh.cells.len())
        .flat_map(|i| {
            let c = mesh.cells.cell(i);
            (0..c.len())
                .map(|k| (mesh.nodes[c[k]], mesh.nodes[c[(k + 1) % c.len()]]))
                .collect::<Vec<_>>()
        })
        .collect()
}

fn mid(a: Point, b: Point) -> Point {
    [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]
}

fn in_box(p: Point, r: &[f64; 4]) -> bool {
    p[0] >= r[0] && p[0] <= r[1] && p[1] >= r[2] && p[1] <= r[3]
}

#[test]
fn p1_edges_follow_the_size_function() {
    let mesh = hertz_mesh(ElementKind::P1);
    let mut inside = 0;
    for (a, b) in edges(&mesh) {
        let len = distance(a, b);
        let h = size(mid(a, b), BLOCK_HMAX, &[HERTZ]);
        // 1e-6: interior nodes come back from spade's normalised 2⁻³⁴ grid (≈ 5e-11 here); the
        // split threshold keeps a margin for it.
        assert!(len <= h * (1.0 + 1e-6), "edge {a:?}–{b:?}: {len} > h = {h}");
        if in_box(a, &HERTZ.region) && in_box(b, &HERTZ.region) {
            inside += 1;
            assert!(len <= HERTZ.hmax * (1.0 + 1e-6));
        }
    }
    // The box is 0.1 × 0.02 at h 0.0025: hundreds of edges inside.
    assert!(inside > 300, "{inside}");
}

#[test]
fn p1_graded_mesh_keeps_the_angle_bound_and_the_area() {
    let limits = MeshLimits::default();
    let cases: [(&[Point], f64, Vec<Refinement>); 3] = [
        (&BLOCK, BLOCK_HMAX, vec![HERTZ]),
        (
            &BLOCK,
            BLOCK_HMAX,
            vec![Refinement {
                region: [0.35, 0.45, 0.38, 0.4],
                hmax: 0.001,
            }],
        ),
        // A point region inside and a line on the top edge of a 2 × 1 block.
        (
            &[[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]],
            0.1,
            vec![
                Refinement {
                    region: [0.5, 0.5, 0.5, 0.5],
                    hmax: 0.005,
                },
                Refinement {
                    region: [1.0, 2.0, 1.0, 1.0],
                    hmax: 0.02,
                },
            ],
        ),
    ];
    for (polygon, hmax, refine) in &cases {
        let mesh = mesh_body(
            &geometry(polygon, *hmax, ElementKind::P1, &[], refine),
            &limits,
        )
        .unwrap();
        // The bound the mesher aims at (MeshLimits::default, 20°); these boundaries have no
        // input angle below it.
        assert!(
            mesh.min_angle_deg() >= limits.min_angle_deg - 1e-9,
            "{}",
            mesh.min_angle_deg()
        );
        let area = signed_area(polygon);
        // Compensated sum of exact-ish cell areas: rounding only.
        assert!((mesh.area() - area).abs() < 1e-12 * area);
        for (a, b) in edges(&mesh) {
            assert!(distance(a, b) <= size(mid(a, b), *hmax, refine) * (1.0 + 1e-6));
        }
    }
}

/// Longest edge of every triangle, and for each interior edge the ratio of its two triangles'.
fn neighbour_ratios(mesh: &Mesh) -> Vec<(f64, Point)> {
    let Cells::Triangles(t) = &mesh.cells else {
        panic!("P1 expected")
    };
    let longest = |c: &[usize; 3]| {
        (0..3)
            .map(|k| distance(mesh.nodes[c[k]], mesh.nodes[c[(k + 1) % 3]]))
            .fold(0.0, f64::max)
    };
    let mut by_edge: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for (i, c) in t.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (c[k], c[(k + 1) % 3]);
            by_edge.entry((a.min(b), a.max(b))).or_default().push(i);
        }
    }
    by_edge
        .iter()
        .filter(|(_, v)| v.len() == 2)
        .map(|(&(a, b), v)| {
            let (p, q) = (longest(&t[v[0]]), longest(&t[v[1]]));
            (p.max(q) / p.min(q), mid(mesh.nodes[a], mesh.nodes[b]))
        })
        .collect()
}

/// How sizes change between neighbours.  Measure: for every interior edge, the ratio of the
/// longest edges of its two triangles.  A Delaunay mesh has this ratio up to ≈ 2 even when
/// uniform (edges between 0.5 h and h); grading may add at most the growth factor per element
/// on top of it.  So: the graded mesh's worst ratio ≤ GRADING × the uniform mesh's worst ratio,
/// and its 99th percentile ≤ GRADING × the uniform one's.  And sizes track h: the mean of
/// (longest edge / h at the triangle's centroid) in each band of distance from the box lies in
/// [0.35, 1] (below 1 by the edge bound; a mesh twice too fine in some band would fail).
#[test]
fn neighbouring_sizes_change_gradually() {
    let graded = hertz_mesh(ElementKind::P1);
    let uniform = mesh_body(
        &geometry(&BLOCK, BLOCK_HMAX, ElementKind::P1, &[], &[]),
        &MeshLimits::default(),
    )
    .unwrap();
    let stats = |m: &Mesh| {
        let mut r: Vec<f64> = neighbour_ratios(m).into_iter().map(|x| x.0).collect();
        r.sort_by(f64::total_cmp);
        (r[r.len() - 1], r[r.len() * 99 / 100])
    };
    let (g_max, g_p99) = stats(&graded);
    let (u_max, u_p99) = stats(&uniform);
    assert!(g_max <= GRADING * u_max, "{g_max} vs uniform {u_max}");
    assert!(g_p99 <= GRADING * u_p99, "{g_p99} vs uniform {u_p99}");

    let Cells::Triangles(t) = &graded.cells else {
        panic!()
    };
    let mut bands = [(0.0, 0usize); 8];
    for c in t {
        let p = c.map(|v| graded.nodes[v]);
        let centroid = [
            (p[0][0] + p[1][0] + p[2][0]) / 3.0,
            (p[0][1] + p[1][1] + p[2][1]) / 3.0,
        ];
        let h = size(centroid, BLOCK_HMAX, &[HERTZ]);
        if h >= BLOCK_HMAX {
            continue;
        }
        let longest = (0..3)
            .map(|k| distance(p[k], p[(k + 1) % 3]))
            .fold(0.0, f64::max);
        // Bands of h: [h_r, 2 h_r), [2 h_r, 4 h_r), …
        let band = ((h / HERTZ.hmax).log2().floor() as usize).min(7);
        bands[band].0 += longest / h;
        bands[band].1 += 1;
    }
    for (i, &(sum, n)) in bands.iter().enumerate() {
        if n > 20 {
            let mean = sum / n as f64;
            assert!((0.35..=1.0).contains(&mean), "band {i}: mean {mean}");
        }
    }
}

#[test]
fn graded_mesh_is_far_smaller_than_the_uniform_fine_one_and_fast() {
    let start = Instant::now();
    let mesh = hertz_mesh(ElementKind::P1);
    let elapsed = start.elapsed();
    // The issue asks for well under a second (measured ≈ 3–8 ms in release builds).
    assert!(elapsed.as_secs_f64() < 1.0, "{elapsed:?}");
    // A uniform mesh at 0.0025 would have area / (0.35 h²) ≈ 146 000 triangles.
    let uniform_fine = 0.32 / (0.35 * HERTZ.hmax * HERTZ.hmax);
    assert!(
        (mesh.cells.len() as f64) < uniform_fine / 10.0,
        "{}",
        mesh.cells.len()
    );
}

/// The estimate lies within [0.8, 1.5] × the real count on graded meshes.  Why that band: the
/// uniform part (0.3 hmax² per triangle, also inside the finest boxes) over-estimates by
/// 8–15 % as documented for `estimate_elements`; the transition zone's constant (0.15 h² per
/// triangle) was fitted on blocks whose own fits ranged 0.136–0.26, i.e. that part may be
/// over-estimated by up to 1.75× or under-estimated by 10 %, and it is under half of the total
/// here; the boundary term and the quadtree's midpoint rule add a few percent.  Leaning high
/// is deliberate: `--max-elements` and the memory preflight must not be surprised.  Q1: exact
/// (no break points here).
#[test]
fn estimate_tracks_the_graded_count() {
    let big = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
    let cases: [(&[Point], f64, Vec<Refinement>); 3] = [
        (&BLOCK, BLOCK_HMAX, vec![HERTZ]),
        (
            &big,
            0.1,
            vec![Refinement {
                region: [0.5, 1.5, 0.4, 0.6],
                hmax: 0.01,
            }],
        ),
        (
            &big,
            0.1,
            vec![Refinement {
                region: [0.5, 0.5, 0.5, 0.5],
                hmax: 0.005,
            }],
        ),
    ];
    for (polygon, hmax, refine) in &cases {
        for element in [ElementKind::P1, ElementKind::Q1] {
            let mesh = mesh_body(
                &geometry(polygon, *hmax, element, &[], refine),
                &MeshLimits::default(),
            )
            .unwrap();
            let actual = mesh.cells.len() as f64;
            let estimate = estimate_elements_refined(polygon, *hmax, refine, element) as f64;
            let nodes = estimate_nodes_refined(polygon, *hmax, refine, element) as f64;
            match element {
                ElementKind::Q1 => {
                    assert_eq!(estimate, actual);
                    assert_eq!(nodes, mesh.nodes.len() as f64);
                }
                ElementKind::P1 => {
                    let r = estimate / actual;
                    assert!(
                        (0.65..=1.35).contains(&r),
                        "{element:?}: {estimate} vs {actual}"
                    );
                    let rn = nodes / mesh.nodes.len() as f64;
                    assert!(
                        (0.65..=1.35).contains(&rn),
                        "nodes {nodes} vs {}",
                        mesh.nodes.len()
                    );
                }
            }
        }
    }
    // Without regions the refined estimate is the plain one.
    for element in [ElementKind::P1, ElementKind::Q1] {
        assert_eq!(
            estimate_elements_refined(&BLOCK, 0.05, &[], element),
            estimate_elements(&BLOCK, 0.05, element)
        );
    }
    // An absurd region saturates instead of running for ever.
    let tiny = [Refinement {
        region: [0.0, 0.8, 0.0, 0.4],
        hmax: 1e-200,
    }];
    assert_eq!(
        estimate_elements_refined(&BLOCK, 0.05, &tiny, ElementKind::P1),
        usize::MAX
    );
    let limits = MeshLimits::default();
    assert!(mesh_body(
        &geometry(&BLOCK, 0.05, ElementKind::P1, &[], &tiny),
        &limits
    )
    .is_err());
}

#[test]
fn q1_graded_grid_follows_the_size_function() {
    let mesh = hertz_mesh(ElementKind::Q1);
    let Cells::Quads(q) = &mesh.cells else {
        panic!("Q1 expected")
    };
    assert!((mesh.area() - 0.32).abs() < 1e-14);
    assert_eq!(mesh.min_angle_deg(), 90.0);
    let mut xs: Vec<f64> = mesh.nodes.iter().map(|p| p[0]).collect();
    let mut ys: Vec<f64> = mesh.nodes.iter().map(|p| p[1]).collect();
    for v in [&mut xs, &mut ys] {
        v.sort_by(f64::total_cmp);
        v.dedup();
    }
    // Tensor grid: every node on a grid line pair.
    assert_eq!(xs.len() * ys.len(), mesh.nodes.len());
    assert_eq!((xs.len() - 1) * (ys.len() - 1), q.len());
    // The box's sides are grid lines (region vertices exact).
    for v in [0.35, 0.45] {
        assert!(xs.contains(&v), "{v}");
    }
    assert!(ys.contains(&0.38) && ys.contains(&0.4));
    // Every cell side ≤ h anywhere on it (h's minimum over the column / row is what the grid
    // follows, so in particular ≤ h at the side's midpoint).
    for (a, b) in edges(&mesh) {
        assert!(distance(a, b) <= size(mid(a, b), BLOCK_HMAX, &[HERTZ]) * (1.0 + 1e-9));
    }
    // Column widths grow by at most the grading factor (+ rounding of the piece count)
    // between neighbours, away from the break points' own short pieces.
    for v in [&xs, &ys] {
        for w in v.windows(3) {
            let (a, b) = (w[1] - w[0], w[2] - w[1]);
            assert!(a.max(b) / a.min(b) <= GRADING * 1.1, "{w:?}");
        }
    }
    // Far fewer cells than the uniform fine grid (320 × 160).
    assert!(q.len() < 320 * 160 / 10, "{}", q.len());
}

/// Two touching bodies with the same refine box and hmax share their interface nodes.
#[test]
fn interface_stays_conforming_with_equal_refine_boxes() {
    let upper = [[0.0, 0.4], [0.8, 0.4], [0.8, 0.6], [0.0, 0.6]];
    let lower = BLOCK;
    // A box straddling the interface y = 0.4.
    let refine = [Refinement {
        region: [0.3, 0.5, 0.35, 0.45],
        hmax: 0.004,
    }];
    let on_interface = |m: &Mesh| {
        let mut x: Vec<f64> = m
            .nodes
            .iter()
            .filter(|p| p[1] == 0.4)
            .map(|p| p[0])
            .collect();
        x.sort_by(f64::total_cmp);
        x
    };
    let crossings = [[0.3, 0.4], [0.5, 0.4]];
    for element in [ElementKind::P1, ElementKind::Q1] {
        let limits = MeshLimits::default();
        let a = mesh_body(
            &geometry(&upper, 0.05, element, &crossings, &refine),
            &limits,
        )
        .unwrap();
        let b = mesh_body(
            &geometry(&lower, 0.05, element, &crossings, &refine),
            &limits,
        )
        .unwrap();
        let (xa, xb) = (on_interface(&a), on_interface(&b));
        // Graded: 0.2 / 0.004 = 50 pieces inside the box alone.
        assert!(xa.len() > 60, "{}", xa.len());
        assert_eq!(xa, xb, "{element:?}");
    }
}

/// Per body of each seed fixture: nodes, cells, FNV-1a hash of the coordinate bits and cell
/// indices, from commit 4856207 (before grading existed).
const SEED_MESHES: &str = "\
exp1.toml 66 50 6a0be9d673d77f4b\n\
exp1.toml 66 50 f9cebb41d61f685a\n\
exp2a.toml 118 204 19a36c46f9b3cc8e\n\
exp2a.toml 118 204 dc1251f6e3c324f5\n\
exp2b.toml 118 204 19a36c46f9b3cc8e\n\
exp2b.toml 118 204 dc1251f6e3c324f5\n\
exp2c.toml 118 204 19a36c46f9b3cc8e\n\
exp2c.toml 118 204 dc1251f6e3c324f5\n\
exp2d.toml 118 204 19a36c46f9b3cc8e\n\
exp2d.toml 118 204 dc1251f6e3c324f5\n\
exp2e.toml 118 204 19a36c46f9b3cc8e\n\
exp2e.toml 118 204 dc1251f6e3c324f5\n\
exp3-body2-h0.08.toml 118 204 19a36c46f9b3cc8e\n\
exp3-body2-h0.08.toml 545 1011 1945d5b135235f54\n\
exp3-body2-h0.1.toml 118 204 19a36c46f9b3cc8e\n\
exp3-body2-h0.1.toml 360 658 8b25178f0237ecc5\n\
exp3-body2-h0.15.toml 118 204 19a36c46f9b3cc8e\n\
exp3-body2-h0.15.toml 179 314 eed022e56a4b3c86\n\
exp3-body2-h0.2.toml 118 204 19a36c46f9b3cc8e\n\
exp3-body2-h0.2.toml 118 204 dc1251f6e3c324f5\n\
exp3-both-h0.08.toml 545 1010 077d402dd9894d98\n\
exp3-both-h0.08.toml 545 1011 1945d5b135235f54\n\
exp3-both-h0.1.toml 360 658 2312836e9ccdc193\n\
exp3-both-h0.1.toml 360 658 8b25178f0237ecc5\n\
exp3-both-h0.15.toml 179 314 e8bc64b335155358\n\
exp3-both-h0.15.toml 179 314 eed022e56a4b3c86\n\
exp3-both-h0.2.toml 118 204 19a36c46f9b3cc8e\n\
exp3-both-h0.2.toml 118 204 dc1251f6e3c324f5\n\
exp4.toml 118 204 19a36c46f9b3cc8e\n\
exp4.toml 118 204 dc1251f6e3c324f5\n\
exp5.toml 118 204 19a36c46f9b3cc8e\n\
exp5.toml 118 204 dc1251f6e3c324f5\n\
exp6a.toml 22 30 a6b883ed973bf152\n\
exp6a.toml 118 204 c91a6e7c0991ad3e\n\
exp6a.toml 360 658 f72fc28e0b843d8b\n\
exp6b.toml 22 30 a6b883ed973bf152\n\
exp6b.toml 118 204 c91a6e7c0991ad3e\n\
exp6b.toml 360 658 f72fc28e0b843d8b\n\
exp7.toml 413 757 95368a3fa1fbf04b\n\
exp7.toml 262 460 a8bbea206d976612";

/// Meshes without regions are the pre-grading meshes: node and cell counts and a hash of every
/// coordinate bit of the seed fixtures, recorded from commit 4856207 (before grading existed).
#[test]
fn seed_fixture_meshes_are_unchanged_without_refine() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/seed");
    let mut names: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    names.sort();
    let mut report = Vec::new();
    for path in names {
        let scene = Scene::from_toml(&std::fs::read_to_string(&path).unwrap()).unwrap();
        assert!(scene.bodies.iter().all(|b| b.refine.is_empty()));
        let meshes = mesh_scene(&scene, &MeshLimits::default()).unwrap();
        for m in &meshes {
            let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
            let mut feed = |x: u64| {
                hash ^= x;
                hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
            };
            for p in &m.nodes {
                feed(p[0].to_bits());
                feed(p[1].to_bits());
            }
            for i in 0..m.cells.len() {
                for &v in m.cells.cell(i) {
                    feed(v as u64);
                }
            }
            report.push(format!(
                "{} {} {} {:016x}",
                path.file_name().unwrap().to_string_lossy(),
                m.nodes.len(),
                m.cells.len(),
                hash
            ));
        }
    }
    let expected = SEED_MESHES;
    let got = report.join("\n");
    assert_eq!(got.trim(), expected.trim(), "got:\n{got}");
}

#[test]
fn scene_refine_crossings_are_nodes_and_preflight_counts_them() {
    let scene = |refine: &str, hmax: f64| {
        format!(
            r#"
[[body]]
name = "block"
polygon = [[0, 0], [0.8, 0], [0.8, 0.4], [0, 0.4]]
hmax = {hmax}
young = 1.0
poisson = 0.3
{refine}

[[dirichlet]]
body = "block"
region = [0, 0.8, 0, 0]
"#
        )
    };
    let refine = "[[body.refine]]\nregion = [0.33, 0.47, 0.38, 0.41]\nhmax = 0.0025\n";
    let graded = Scene::from_toml(&scene(refine, 0.05)).unwrap();
    let fine = Scene::from_toml(&scene("", 0.0025)).unwrap();
    let limits = MeshLimits::default();
    let mesh = &mesh_scene(&graded, &limits).unwrap()[0];
    // The box crosses the top edge? No: it reaches past it (0.41); its sides cross the top edge
    // at x = 0.33 and 0.47, which are nodes.
    for x in [0.33, 0.47] {
        assert!(
            mesh.nodes[..mesh.boundary.len()]
                .iter()
                .any(|p| p[0] == x && p[1] == 0.4),
            "{x}"
        );
    }
    // What `signorini check` reports: the preflight estimate, and the real meshes.
    let pg = signorini_core::preflight::preflight(&graded, &limits).unwrap();
    let pf = signorini_core::preflight::preflight(&fine, &limits).unwrap();
    assert!(
        pg.elements * 10 < pf.elements,
        "{} vs {}",
        pg.elements,
        pf.elements
    );
    let fine_mesh = &mesh_scene(&fine, &limits).unwrap()[0];
    assert!(mesh.cells.len() * 10 < fine_mesh.cells.len());
    let _ = bounding_box(&BLOCK);
}

/// A Hertz cylinder (half-disc of radius 0.5, 128 segments) refined at its lowest point: the
/// size function is followed on a curved boundary, angles and area hold, and the same scene
/// in other units (× 1000) gives the same mesh scaled.
#[test]
fn curved_body_refined_at_the_contact_point() {
    let r = 0.5;
    let n = 128;
    let mut polygon: Vec<Point> = (0..=n)
        .map(|i| {
            let t = std::f64::consts::PI * (1.0 + i as f64 / n as f64);
            [r * t.cos(), 0.5 + r * t.sin()]
        })
        .collect();
    polygon.dedup();
    let refine = [Refinement {
        region: [-0.05, 0.05, 0.0, 0.01],
        hmax: 0.002,
    }];
    let limits = MeshLimits::default();
    let mesh = mesh_body(
        &geometry(&polygon, 0.05, ElementKind::P1, &[], &refine),
        &limits,
    )
    .unwrap();
    // The uniform mesher already falls below 20° at the two corners where the flat side (split
    // at 0.05) meets the arc (edges of 0.012) — the documented "boundary edges much shorter than
    // their neighbours" case.  Grading must not make it worse, and must keep 20° elsewhere.
    let uniform = mesh_body(
        &geometry(&polygon, 0.05, ElementKind::P1, &[], &[]),
        &limits,
    )
    .unwrap();
    assert!(mesh.min_angle_deg() >= uniform.min_angle_deg().min(limits.min_angle_deg) - 1e-9);
    let Cells::Triangles(t) = &mesh.cells else {
        panic!()
    };
    for c in t {
        let p = c.map(|v| mesh.nodes[v]);
        let near_corner = p
            .iter()
            .any(|q| distance(*q, [-0.5, 0.5]) < 0.06 || distance(*q, [0.5, 0.5]) < 0.06);
        if !near_corner {
            let one = Mesh {
                nodes: p.to_vec(),
                cells: Cells::Triangles(vec![[0, 1, 2]]),
                boundary: vec![],
            };
            assert!(one.min_angle_deg() >= limits.min_angle_deg - 1e-9, "{p:?}");
        }
    }
    let area = signed_area(&polygon).abs();
    assert!((mesh.area() - area).abs() < 1e-12 * area);
    for (a, b) in edges(&mesh) {
        assert!(distance(a, b) <= size(mid(a, b), 0.05, &refine) * (1.0 + 1e-6));
    }
    // The polygon's vertices stay nodes.
    for v in &polygon {
        assert!(mesh.nodes.contains(v), "{v:?}");
    }

    let scale = 1000.0;
    let scaled: Vec<Point> = polygon
        .iter()
        .map(|p| [p[0] * scale, p[1] * scale])
        .collect();
    let scaled_refine = [Refinement {
        region: refine[0].region.map(|v| v * scale),
        hmax: refine[0].hmax * scale,
    }];
    let big = mesh_body(
        &BodyGeometry {
            tol: 1e-9 * scale,
            ..geometry(&scaled, 0.05 * scale, ElementKind::P1, &[], &scaled_refine)
        },
        &limits,
    )
    .unwrap();
    assert_eq!(big.nodes.len(), mesh.nodes.len());
    assert_eq!(big.cells, mesh.cells);
    // Coordinates agree to rounding (the snapped unit coordinates are identical).
    for (p, q) in big.nodes.iter().zip(&mesh.nodes) {
        assert!(
            distance([p[0] / scale, p[1] / scale], *q) < 1e-12,
            "{p:?} {q:?}"
        );
    }
    let _ = bounding_box(&polygon);
}
