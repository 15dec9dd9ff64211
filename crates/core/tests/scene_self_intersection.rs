//! `geometry::self_intersection` (R-tree of edge boxes) against the quadratic test of every pair
//! of edges it replaced, kept here as the reference: the same pair, or `None`, on random,
//! near-degenerate and large polygons.

use proptest::prelude::*;
use signorini_core::geometry::{distance, orient, segments_touch, self_intersection, Point};
use signorini_core::scene::Scene;

/// The former implementation, verbatim: every pair of non-adjacent edges, then spikes.
fn brute_force(polygon: &[Point], tol: f64) -> Option<(usize, usize)> {
    let n = polygon.len();
    for i in 0..n {
        for j in (i + 1)..n {
            let adjacent = j == i + 1 || (i == 0 && j == n - 1);
            if adjacent {
                continue;
            }
            let (a, b) = (polygon[i], polygon[(i + 1) % n]);
            let (c, d) = (polygon[j], polygon[(j + 1) % n]);
            if segments_touch(a, b, c, d, tol) {
                return Some((i, j));
            }
        }
    }
    for i in 0..n {
        let (a, b, c) = (polygon[i], polygon[(i + 1) % n], polygon[(i + 2) % n]);
        let ab = distance(a, b).max(tol);
        let bc = distance(b, c).max(tol);
        let collinear = orient(a, b, c).abs() / (ab * bc) <= 1e-12;
        let back = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]) < 0.0;
        if collinear && back {
            return Some((i, (i + 1) % n));
        }
    }
    None
}

/// A star-shaped (hence simple) polygon: increasing angles, radii in [r0, r1].
fn star(n: usize, r0: f64, r1: f64, seed: u64) -> Vec<Point> {
    let mut state = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            let r = r0 + (r1 - r0) * next();
            [r * t.cos(), r * t.sin()]
        })
        .collect()
}

/// Tolerances the scene uses (1e-8 × size), none, and a coarse one that makes near edges touch.
fn tolerance() -> impl Strategy<Value = f64> {
    prop_oneof![Just(0.0), Just(1e-12), Just(1e-8), Just(0.05), Just(0.3)]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Vertices on a small integer grid: many collinear runs, coincident vertices, edges through
    /// vertices, spikes — the degenerate cases of the predicate.
    #[test]
    fn grid_polygons_agree(
        polygon in prop::collection::vec((-4i32..=4, -4i32..=4), 3..14),
        tol in tolerance(),
    ) {
        let polygon: Vec<Point> = polygon.into_iter().map(|(x, y)| [x as f64, y as f64]).collect();
        prop_assert_eq!(self_intersection(&polygon, tol), brute_force(&polygon, tol));
    }

    /// Random real coordinates: mostly crossing polygons, the first pair must match.
    #[test]
    fn random_polygons_agree(
        polygon in prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0), 3..40),
        tol in tolerance(),
    ) {
        let polygon: Vec<Point> = polygon.into_iter().map(|(x, y)| [x, y]).collect();
        prop_assert_eq!(self_intersection(&polygon, tol), brute_force(&polygon, tol));
    }

    /// Simple star-shaped polygons with one vertex pulled to within about `tol` of a
    /// non-adjacent edge (inside, on or just outside the tolerance), at large offsets too.
    #[test]
    fn near_touching_polygons_agree(
        n in 5usize..60,
        seed in any::<u64>(),
        pick in any::<prop::sample::Index>(),
        edge in any::<prop::sample::Index>(),
        along in 0.0f64..=1.0,
        factor in prop_oneof![Just(0.0), Just(0.5), Just(0.999_999), Just(1.000_001), Just(2.0)],
        offset in prop_oneof![Just(0.0), Just(1e6)],
    ) {
        let tol = 1e-8;
        let mut polygon = star(n, 0.5, 1.0, seed);
        let v = pick.index(n);
        let e = edge.index(n);
        // Pull vertex v onto edge e (if non-adjacent), then push it off by factor × tol along
        // the edge's normal.
        if e != v && (e + 1) % n != v {
            let (a, b) = (polygon[e], polygon[(e + 1) % n]);
            let len = distance(a, b);
            let normal = [(b[1] - a[1]) / len, -(b[0] - a[0]) / len];
            polygon[v] = [
                a[0] + along * (b[0] - a[0]) + factor * tol * normal[0],
                a[1] + along * (b[1] - a[1]) + factor * tol * normal[1],
            ];
        }
        for p in &mut polygon {
            p[0] += offset;
            p[1] -= offset;
        }
        prop_assert_eq!(self_intersection(&polygon, tol), brute_force(&polygon, tol));
    }

    /// Simple polygons stay simple; clockwise and counter-clockwise alike.
    #[test]
    fn star_polygons_are_simple(n in 3usize..200, seed in any::<u64>(), reverse in any::<bool>()) {
        let mut polygon = star(n, 0.2, 1.0, seed);
        if reverse {
            polygon.reverse();
        }
        prop_assert_eq!(brute_force(&polygon, 1e-8), None);
        prop_assert_eq!(self_intersection(&polygon, 1e-8), None);
    }
}

#[test]
fn known_cases() {
    let bowtie = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
    assert_eq!(self_intersection(&bowtie, 1e-12), Some((0, 2)));
    // A spike: adjacent edges folding back.
    let spike = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
    assert_eq!(self_intersection(&spike, 1e-12), brute_force(&spike, 1e-12));
    assert!(self_intersection(&spike, 1e-12).is_some());
    // A vertex exactly on a non-adjacent edge (touching, not crossing).
    let touch = [[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [2.0, 0.0], [0.0, 2.0]];
    assert_eq!(self_intersection(&touch, 1e-12), Some((0, 2)));
    // Triangles and fewer: only spikes can be found.
    assert_eq!(
        self_intersection(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], 1e-12),
        None
    );
    assert_eq!(self_intersection(&[], 1e-12), None);
    // Non-finite coordinates: None, like the pairwise test (whose comparisons all fail).
    let nan = [[0.0, 0.0], [f64::NAN, 0.0], [1.0, 1.0], [0.0, 1.0]];
    assert_eq!(self_intersection(&nan, 1e-12), brute_force(&nan, 1e-12));
}

#[test]
fn large_polygons_agree_with_the_reference() {
    // 2 000 vertices: the reference takes ~2 M pair tests, still quick in release.
    let simple = star(2000, 0.9, 1.0, 7);
    assert_eq!(self_intersection(&simple, 1e-8), None);
    assert_eq!(brute_force(&simple, 1e-8), None);
    let mut crossing = simple.clone();
    crossing.swap(500, 1500);
    assert_eq!(
        self_intersection(&crossing, 1e-8),
        brute_force(&crossing, 1e-8)
    );
    assert!(self_intersection(&crossing, 1e-8).is_some());
}

fn polygon_scene(polygon: &[Point]) -> String {
    let vertices: Vec<String> = polygon
        .iter()
        .map(|p| format!("[{:e}, {:e}]", p[0], p[1]))
        .collect();
    format!(
        "[[body]]\nname = \"disc\"\npolygon = [{}]\nhmax = 0.1\nyoung = 1.0\npoisson = 0.3\n\
         [[dirichlet]]\nbody = \"disc\"\nregion = [-2, 2, -2, 0]\n",
        vertices.join(", ")
    )
}

/// A 40 000-vertex simple polygon validates (the quadratic test took 85 s on such input).
#[test]
fn forty_thousand_vertex_polygon_validates() {
    let polygon = star(40_000, 0.9, 1.0, 11);
    let scene = Scene::from_toml(&polygon_scene(&polygon)).unwrap();
    assert_eq!(scene.bodies[0].polygon.len(), 40_000);
}

/// Timing of the 40 000-vertex case, printed (not asserted):
/// `cargo test --release -p signorini-core --test scene_self_intersection -- --ignored --nocapture`
#[test]
#[ignore]
fn time_forty_thousand_vertices() {
    for (label, r0) in [
        ("circle, radii in [0.9999, 1]", 0.9999),
        ("jagged circle, radii in [0.9, 1]", 0.9),
        ("spiky star, radii in [0.2, 1]", 0.2),
    ] {
        let polygon = star(40_000, r0, 1.0, 11);
        let start = std::time::Instant::now();
        let found = self_intersection(&polygon, 1e-8 * 2.0);
        let t = start.elapsed();
        println!(
            "{label}: self_intersection {:.3} s -> {found:?}",
            t.as_secs_f64()
        );
        let text = polygon_scene(&polygon);
        let start = std::time::Instant::now();
        let scene = Scene::from_toml(&text);
        println!(
            "{label}: Scene::from_toml (parse + validation) {:.3} s -> valid: {}",
            start.elapsed().as_secs_f64(),
            scene.is_ok()
        );
    }
}
