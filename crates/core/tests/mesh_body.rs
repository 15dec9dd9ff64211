//! Meshing: geometry and quality invariants of P1/Q1 meshes, conformity of interfaces, scale
//! invariance, limits, and box/polygon crossings.

#![allow(clippy::unwrap_used)] // tests may unwrap (helpers included)

use std::collections::HashMap;
use std::time::Instant;

use proptest::prelude::*;
use signorini_core::geometry::{distance, orient, signed_area, Point};
use signorini_core::mesh::{
    box_crossings, estimate_elements, mesh_body, BodyGeometry, Cells, ElementKind, Mesh, MeshError,
    MeshLimits,
};

const UPPER: [Point; 4] = [[0.0, 1.0], [2.0, 1.0], [2.0, 2.0], [0.0, 2.0]];
const LOWER: [Point; 4] = [[1.0, 0.0], [3.0, 0.0], [3.0, 1.0], [1.0, 1.0]];
const WEDGE: [Point; 6] = [
    [0.0, 3.0],
    [2.25, 1.5],
    [2.75, 1.5],
    [5.0, 3.0],
    [5.0, 4.0],
    [0.0, 4.0],
];
const BEAM: [Point; 4] = [[0.0, 0.5], [5.0, 0.5], [5.0, 1.5], [0.0, 1.5]];

fn perimeter(polygon: &[Point]) -> f64 {
    (0..polygon.len())
        .map(|i| distance(polygon[i], polygon[(i + 1) % polygon.len()]))
        .sum()
}

fn body<'a>(polygon: &'a [Point], hmax: f64, breakpoints: &'a [Point]) -> BodyGeometry<'a> {
    BodyGeometry {
        polygon,
        hmax,
        element: ElementKind::P1,
        breakpoints,
        refine: &[],
        tol: 1e-9,
    }
}

fn p1(polygon: &[Point], hmax: f64, breakpoints: &[Point]) -> Mesh {
    mesh_body(&body(polygon, hmax, breakpoints), &MeshLimits::default()).unwrap()
}

/// Checks that `mesh` is a valid conforming mesh of `polygon`: counter-clockwise cells, every
/// node used, every interior edge shared by exactly two cells in opposite directions, the
/// boundary exactly the unmatched cell edges (body on the left) forming one closed loop, area
/// and perimeter exact, every edge ≤ hmax.  Returns the minimum angle.
fn check_mesh(mesh: &Mesh, polygon: &[Point], hmax: f64) -> f64 {
    let n = mesh.nodes.len();
    let mut used = vec![false; n];
    let mut directed: HashMap<(usize, usize), usize> = HashMap::new();
    for i in 0..mesh.cells.len() {
        let c = mesh.cells.cell(i);
        let m = c.len();
        for k in 0..m {
            used[c[k]] = true;
            let twice = orient(
                mesh.nodes[c[k]],
                mesh.nodes[c[(k + 1) % m]],
                mesh.nodes[c[(k + 2) % m]],
            );
            assert!(
                twice > 0.0,
                "cell {i} is not counter-clockwise/convex at corner {k}"
            );
            *directed.entry((c[k], c[(k + 1) % m])).or_default() += 1;
        }
    }
    assert!(used.iter().all(|&u| u), "unused nodes");
    assert!(
        directed.values().all(|&c| c == 1),
        "a directed edge occurs twice"
    );
    let mut unmatched: Vec<(usize, usize)> = directed
        .keys()
        .filter(|&&(a, b)| !directed.contains_key(&(b, a)))
        .copied()
        .collect();
    unmatched.sort();
    let mut boundary: Vec<(usize, usize)> = mesh.boundary.iter().map(|&[a, b]| (a, b)).collect();
    boundary.sort();
    assert_eq!(boundary, unmatched, "boundary != unmatched cell edges");
    // One closed loop.
    let next: HashMap<usize, usize> = mesh.boundary.iter().map(|&[a, b]| (a, b)).collect();
    assert_eq!(
        next.len(),
        mesh.boundary.len(),
        "a node starts two boundary edges"
    );
    let start = mesh.boundary[0][0];
    let (mut v, mut steps) = (next[&start], 1);
    while v != start {
        v = next[&v];
        steps += 1;
        assert!(steps <= mesh.boundary.len());
    }
    assert_eq!(steps, mesh.boundary.len(), "boundary is not one loop");
    // Every boundary node lies on the polygon boundary.
    let magnitude = polygon
        .iter()
        .flatten()
        .fold(1e-300_f64, |m, v| m.max(v.abs()));
    for &[a, _] in &mesh.boundary {
        let p = mesh.nodes[a];
        let d = (0..polygon.len())
            .map(|i| {
                signorini_core::geometry::project_on_segment(
                    p,
                    polygon[i],
                    polygon[(i + 1) % polygon.len()],
                )
                .1
            })
            .fold(f64::INFINITY, f64::min);
        assert!(
            d <= 1e-14 * magnitude,
            "boundary node {p:?} off the polygon by {d}"
        );
    }
    let area = signed_area(polygon).abs();
    assert!(
        (mesh.area() - area).abs() <= 1e-12 * area,
        "area {} vs {area}",
        mesh.area()
    );
    let per = perimeter(polygon);
    assert!(
        (mesh.boundary_length() - per).abs() <= 1e-12 * per,
        "perimeter"
    );
    assert!(
        mesh.max_edge() <= hmax * (1.0 + 1e-9),
        "max edge {} > hmax {hmax}",
        mesh.max_edge()
    );
    mesh.min_angle_deg()
}

/// Smallest interior angle of a counter-clockwise convex polygon, in degrees.
fn input_angle_deg(polygon: &[Point]) -> f64 {
    let n = polygon.len();
    (0..n)
        .map(|i| {
            let (a, b, c) = (polygon[(i + n - 1) % n], polygon[i], polygon[(i + 1) % n]);
            let u = [a[0] - b[0], a[1] - b[1]];
            let v = [c[0] - b[0], c[1] - b[1]];
            (u[0] * v[1] - u[1] * v[0])
                .abs()
                .atan2(u[0] * v[0] + u[1] * v[1])
                .to_degrees()
        })
        .fold(180.0, f64::min)
}

/// Largest length ratio of two consecutive boundary edges.
fn boundary_ratio(mesh: &Mesh) -> f64 {
    let len = |e: &[usize; 2]| distance(mesh.nodes[e[0]], mesh.nodes[e[1]]);
    let mut next = HashMap::new();
    for e in &mesh.boundary {
        next.insert(e[0], *e);
    }
    mesh.boundary
        .iter()
        .map(|e| {
            let (a, b) = (len(e), len(&next[&e[1]]));
            a.max(b) / a.min(b)
        })
        .fold(1.0, f64::max)
}

fn is_node(mesh: &Mesh, p: Point, tol: f64) -> bool {
    mesh.nodes.iter().any(|&q| distance(p, q) <= tol)
}

#[test]
fn seed_bodies_have_short_edges_and_good_angles() {
    for hmax in [0.2, 0.08, 0.02] {
        for (polygon, corner) in [(&UPPER, [1.0, 1.0]), (&LOWER, [2.0, 1.0])] {
            let mesh = p1(polygon, hmax, &[corner]);
            let angle = check_mesh(&mesh, polygon, hmax);
            assert!(angle >= 20.0, "hmax {hmax}: min angle {angle}");
            assert!(is_node(&mesh, corner, 0.0));
        }
    }
    let mesh = p1(&WEDGE, 0.2, &[]);
    let angle = check_mesh(&mesh, &WEDGE, 0.2);
    assert!(angle >= 20.0, "wedge: min angle {angle}");
    let mesh = p1(&BEAM, 0.2, &[[2.25, 1.5], [2.75, 1.5]]);
    assert!(check_mesh(&mesh, &BEAM, 0.2) >= 20.0);
}

#[test]
fn element_count_is_close_to_the_estimate() {
    for hmax in [0.2, 0.08, 0.02] {
        let mesh = p1(&WEDGE, hmax, &[]);
        let estimate = estimate_elements(&WEDGE, hmax, ElementKind::P1) as f64;
        let ratio = mesh.cells.len() as f64 / estimate;
        assert!(
            (0.6..=1.3).contains(&ratio),
            "hmax {hmax}: {} vs {estimate}",
            mesh.cells.len()
        );
    }
}

#[test]
fn p1_boundary_is_the_rule_discretisation() {
    // [0,2] split into 10, [0,1] into 5 at hmax 0.2; breakpoint (1,1) on the bottom edge.
    let mesh = p1(&UPPER, 0.2, &[[1.0, 1.0]]);
    assert_eq!(mesh.boundary.len(), 30);
    // hmax 0.15 with breakpoint (0.5, 1): [0,0.5] → 4 pieces, [0.5,2] → 10, [0,1] → 7.
    let mesh = p1(&UPPER, 0.15, &[[0.5, 1.0]]);
    assert_eq!(mesh.boundary.len(), 4 + 10 + 7 + 14 + 7);
    for i in 0..4 {
        assert!(is_node(&mesh, [0.125 * i as f64, 1.0], 1e-15));
    }
}

#[test]
fn breakpoints_on_the_boundary_become_nodes() {
    let neumann = box_crossings(&UPPER, &[1.03, 1.77, 2.0, 2.0], 1e-9);
    assert_eq!(neumann, vec![[1.03, 2.0], [1.77, 2.0]]);
    let off = [0.7, 1.5]; // inside the body: ignored
    let near_corner = [2.0 + 1e-12, 2.0]; // within tol of a vertex: no extra node
    let mut points = neumann.clone();
    points.extend([off, near_corner, [1.0, 1.0]]);
    let mesh = p1(&UPPER, 0.08, &points);
    check_mesh(&mesh, &UPPER, 0.08);
    for p in neumann.iter().chain(&[[1.0, 1.0]]) {
        assert!(
            mesh.boundary.iter().any(|&[a, _]| mesh.nodes[a] == *p),
            "{p:?}"
        );
    }
    assert!(mesh
        .boundary
        .iter()
        .all(|&[a, _]| distance(mesh.nodes[a], off) > 0.1));
    let close = mesh
        .nodes
        .iter()
        .filter(|&&q| distance(q, [2.0, 2.0]) < 1e-6)
        .count();
    assert_eq!(close, 1);
    // The seed's top edge at hmax 0.08 gets x = 1 only through the breakpoint.
    let plain = p1(&UPPER, 0.08, &[]);
    assert!(!is_node(&plain, [1.0, 2.0], 1e-9));
    let with = p1(&UPPER, 0.08, &[[1.0, 2.0]]);
    assert!(is_node(&with, [1.0, 2.0], 0.0));
}

/// Boundary nodes of `mesh` on the segment a–b.
fn nodes_on(mesh: &Mesh, a: Point, b: Point) -> Vec<Point> {
    let mut v: Vec<Point> = mesh
        .boundary
        .iter()
        .map(|&[i, _]| mesh.nodes[i])
        .filter(|&p| signorini_core::geometry::project_on_segment(p, a, b).1 <= 1e-12)
        .collect();
    v.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
    v
}

fn same_points(a: &[Point], b: &[Point]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(p, q)| distance(*p, *q) <= 1e-12)
}

#[test]
fn equal_hmax_gives_conforming_interfaces() {
    for hmax in [0.2, 0.15, 0.07] {
        let upper = p1(&UPPER, hmax, &[[1.0, 1.0]]);
        let lower = p1(&LOWER, hmax, &[[2.0, 1.0]]);
        let (a, b) = (
            nodes_on(&upper, [1.0, 1.0], [2.0, 1.0]),
            nodes_on(&lower, [1.0, 1.0], [2.0, 1.0]),
        );
        assert!(a.len() >= 6);
        assert!(same_points(&a, &b), "hmax {hmax}");
    }
    let upper = p1(&UPPER, 0.2, &[[1.0, 1.0]]);
    let lower = p1(&LOWER, 0.15, &[[2.0, 1.0]]);
    let (a, b) = (
        nodes_on(&upper, [1.0, 1.0], [2.0, 1.0]),
        nodes_on(&lower, [1.0, 1.0], [2.0, 1.0]),
    );
    assert!(!same_points(&a, &b));
    // A slanted interface traversed in opposite directions by the two bodies.
    let left = [[0.0, 0.0], [1.3, 0.4], [0.2, 1.7]];
    let right = [[1.3, 0.4], [2.0, 1.5], [0.2, 1.7]];
    for hmax in [0.3, 0.11] {
        let l = p1(&left, hmax, &[]);
        let r = p1(&right, hmax, &[]);
        check_mesh(&l, &left, hmax);
        check_mesh(&r, &right, hmax);
        let (a, b) = (
            nodes_on(&l, left[1], left[2]),
            nodes_on(&r, left[1], left[2]),
        );
        assert!(a.len() > 5 && same_points(&a, &b));
    }
}

#[test]
fn scaling_to_mm_scales_the_mesh() {
    let awkward = [[0.1, 0.3], [1.7, 0.2], [1.9, 1.3], [0.3, 1.1]];
    let cases: [(&[Point], f64, Vec<Point>); 3] = [
        (&UPPER, 0.08, vec![[1.0, 1.0], [1.0, 2.0]]),
        (&WEDGE, 0.2, vec![[2.5, 4.0], [3.5, 4.0]]),
        (&awkward, 0.1, vec![[1.0, 0.25]]),
    ];
    for (polygon, hmax, breaks) in cases {
        let m = p1(polygon, hmax, &breaks);
        let scale = |v: &[Point]| {
            v.iter()
                .map(|p| [p[0] * 1000.0, p[1] * 1000.0])
                .collect::<Vec<_>>()
        };
        let (poly_mm, breaks_mm) = (scale(polygon), scale(&breaks));
        let g = BodyGeometry {
            tol: 1e-6,
            ..body(&poly_mm, hmax * 1000.0, &breaks_mm)
        };
        let mm = mesh_body(&g, &MeshLimits::default()).unwrap();
        assert_eq!(m.cells, mm.cells);
        assert_eq!(m.boundary, mm.boundary);
        assert_eq!(m.nodes.len(), mm.nodes.len());
        for (p, q) in m.nodes.iter().zip(&mm.nodes) {
            let extent = 5000.0;
            assert!(distance([p[0] * 1000.0, p[1] * 1000.0], *q) <= 1e-9 * extent);
        }
    }
}

#[test]
fn meshing_is_deterministic_and_orientation_free() {
    let a = p1(&WEDGE, 0.1, &[[2.5, 4.0]]);
    let b = p1(&WEDGE, 0.1, &[[2.5, 4.0]]);
    assert_eq!(a, b);
    let mut cw = WEDGE;
    cw.reverse();
    let c = p1(&cw, 0.1, &[[2.5, 4.0]]);
    check_mesh(&c, &WEDGE, 0.1);
    let mut nodes_a: Vec<Point> = a.boundary.iter().map(|&[i, _]| a.nodes[i]).collect();
    let mut nodes_c: Vec<Point> = c.boundary.iter().map(|&[i, _]| c.nodes[i]).collect();
    let key = |p: &Point, q: &Point| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1]));
    nodes_a.sort_by(key);
    nodes_c.sort_by(key);
    assert_eq!(nodes_a, nodes_c);
}

#[test]
fn awkward_polygons_mesh_validly() {
    // Non-convex L, a thin sliver (3° input angle), tiny boundary features.
    let l_shape = [
        [0.0, 0.0],
        [2.0, 0.0],
        [2.0, 0.5],
        [0.5, 0.5],
        [0.5, 2.0],
        [0.0, 2.0],
    ];
    let mesh = p1(&l_shape, 0.1, &[]);
    assert!(check_mesh(&mesh, &l_shape, 0.1) >= 20.0);
    let sliver = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.05]];
    let mesh = p1(&sliver, 0.1, &[]);
    let angle = check_mesh(&mesh, &sliver, 0.1);
    assert!(angle > 2.5, "sliver min angle {angle}");
    // hmax larger than the body: no split at all.
    let coarse = p1(&UPPER, 10.0, &[]);
    check_mesh(&coarse, &UPPER, 10.0);
    assert_eq!((coarse.nodes.len(), coarse.cells.len()), (4, 2));
    let tiny = [[1e-4, 1.0], [2.0 - 1e-5, 2.0], [1.0 + 1e-6, 1.0]];
    let mesh = p1(&UPPER, 0.2, &tiny);
    check_mesh(&mesh, &UPPER, 0.2);
    for p in tiny {
        assert!(is_node(&mesh, p, 0.0));
    }
}

#[test]
fn oversized_requests_are_refused_quickly() {
    let hmax = (2.0 / (1e7 * 0.3_f64)).sqrt(); // about 1e7 triangles
    let start = Instant::now();
    let err = mesh_body(&body(&UPPER, hmax, &[]), &MeshLimits::default()).unwrap_err();
    assert!(start.elapsed().as_secs_f64() < 0.5);
    match &err {
        MeshError::TooManyElements { estimated, limit } => {
            assert!(
                *estimated > 9_000_000 && *estimated < 12_000_000,
                "{estimated}"
            );
            assert_eq!(*limit, 5_000_000);
        }
        e => panic!("unexpected {e}"),
    }
    let message = err.to_string();
    assert!(
        message.contains("5000000") && message.contains("raise"),
        "{message}"
    );
    let small = MeshLimits {
        max_elements: 100,
        ..MeshLimits::default()
    };
    assert!(matches!(
        mesh_body(&body(&UPPER, 0.1, &[]), &small),
        Err(MeshError::TooManyElements { .. })
    ));
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let limits = MeshLimits::default();
    for hmax in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            mesh_body(&body(&UPPER, hmax, &[]), &limits),
            Err(MeshError::InvalidParameter { .. })
        ));
    }
    let line = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
    let two = [[0.0, 0.0], [1.0, 0.0]];
    let nan = [[0.0, 0.0], [1.0, f64::NAN], [0.0, 1.0]];
    let bowtie = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
    for polygon in [&line[..], &two, &nan, &bowtie] {
        let result = mesh_body(&body(polygon, 0.1, &[]), &limits);
        assert!(
            matches!(result, Err(MeshError::DegeneratePolygon { .. })),
            "{result:?}"
        );
    }
    let steep = MeshLimits {
        min_angle_deg: 50.0,
        ..limits
    };
    assert!(mesh_body(&body(&UPPER, 0.1, &[]), &steep).is_err());
    let q1 = BodyGeometry {
        element: ElementKind::Q1,
        ..body(&WEDGE, 0.2, &[])
    };
    assert!(matches!(
        mesh_body(&q1, &limits),
        Err(MeshError::NotARectangle)
    ));
}

#[test]
fn q1_grids() {
    let q1 = |polygon: &[Point], hmax: f64, breaks: &[Point]| {
        let g = BodyGeometry {
            element: ElementKind::Q1,
            ..body(polygon, hmax, breaks)
        };
        mesh_body(&g, &MeshLimits::default()).unwrap()
    };
    let mesh = q1(&UPPER, 0.2, &[]);
    assert_eq!(
        (mesh.nodes.len(), mesh.cells.len(), mesh.boundary.len()),
        (66, 50, 30)
    );
    assert!(matches!(mesh.cells, Cells::Quads(_)));
    assert!((check_mesh(&mesh, &UPPER, 0.2) - 90.0).abs() < 1e-9);
    // Clockwise, starting elsewhere, with an extra vertex on a side.
    let odd = [[2.0, 1.0], [1.0, 1.0], [0.0, 1.0], [0.0, 2.0], [2.0, 2.0]];
    let mesh = q1(&odd, 0.2, &[]);
    check_mesh(&mesh, &UPPER, 0.2);
    assert_eq!(mesh.cells.len(), 50);
    // Breakpoint on the bottom (x = 1.05) adds its own split points: bottom [0,1.05] → 6
    // pieces, [1.05,2] → 5; union with the top's 11 x-values.
    let mesh = q1(&UPPER, 0.2, &[[1.05, 1.0]]);
    check_mesh(&mesh, &UPPER, 0.2);
    let mut xs: Vec<f64> = (0..=10).map(|i| 0.2 * i as f64).collect();
    xs.extend((1..6).map(|i| 1.05 * i as f64 / 6.0));
    xs.extend((0..5).map(|i| 1.05 + 0.95 * i as f64 / 5.0));
    xs.sort_by(f64::total_cmp);
    xs.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    assert_eq!(mesh.nodes.len(), xs.len() * 6);
    assert_eq!(mesh.cells.len(), (xs.len() - 1) * 5);
    // Experiment 1: both seed rectangles, equal hmax → conforming interface.
    let upper = q1(&UPPER, 0.1, &[[1.0, 1.0]]);
    let lower = q1(&LOWER, 0.1, &[[2.0, 1.0]]);
    assert!(same_points(
        &nodes_on(&upper, [1.0, 1.0], [2.0, 1.0]),
        &nodes_on(&lower, [1.0, 1.0], [2.0, 1.0])
    ));
}

#[test]
fn box_crossings_of_the_seed_regions() {
    let tol = 1e-9;
    assert_eq!(
        box_crossings(&UPPER, &[1.0, 2.0, 2.0, 2.0], tol),
        vec![[1.0, 2.0], [2.0, 2.0]]
    );
    // The thin contact box also touches the side edges it overlaps (x = 2 of the upper body for
    // y ∈ [1, 1.01], x = 1 of the lower body for y ∈ [0.99, 1]): the overlap ends are reported.
    let contact = [1.0, 2.0, 0.99, 1.01];
    assert_eq!(
        box_crossings(&UPPER, &contact, tol),
        vec![[1.0, 1.0], [2.0, 1.0], [2.0, 1.01]]
    );
    assert_eq!(
        box_crossings(&LOWER, &contact, tol),
        vec![[1.0, 0.99], [1.0, 1.0], [2.0, 1.0]]
    );
    assert_eq!(
        box_crossings(&UPPER, &[0.0, 0.0, 1.0, 2.0], tol),
        vec![[0.0, 1.0], [0.0, 2.0]]
    );
    assert_eq!(
        box_crossings(&LOWER, &[3.0, 3.0, 0.0, 1.0], tol),
        vec![[3.0, 0.0], [3.0, 1.0]]
    );
    assert_eq!(
        box_crossings(&LOWER, &[1.0, 3.0, 0.0, 0.0], tol),
        vec![[1.0, 0.0], [3.0, 0.0]]
    );
    assert_eq!(
        box_crossings(&WEDGE, &[2.5, 3.5, 4.0, 4.0], tol),
        vec![[2.5, 4.0], [3.5, 4.0]]
    );
    assert_eq!(
        box_crossings(&BEAM, &[2.25, 2.75, 1.49, 1.51], tol),
        vec![[2.25, 1.5], [2.75, 1.5]]
    );
    // Point boxes: on the boundary, off it.
    assert_eq!(
        box_crossings(&UPPER, &[1.0, 1.0, 2.0, 2.0], tol),
        vec![[1.0, 2.0]]
    );
    assert!(box_crossings(&UPPER, &[1.0, 1.0, 1.5, 1.5], tol).is_empty());
    // A box inside the body, a box containing it, a box far away.
    assert!(box_crossings(&UPPER, &[0.5, 1.5, 1.2, 1.8], tol).is_empty());
    assert!(box_crossings(&UPPER, &[-1.0, 3.0, 0.0, 3.0], tol).is_empty());
    assert!(box_crossings(&UPPER, &[5.0, 6.0, 5.0, 6.0], tol).is_empty());
    // Vertical box sides crossing the wedge's slanted edge and its top.
    let got = box_crossings(&WEDGE, &[1.0, 2.0, 0.0, 5.0], tol);
    let want = [
        [1.0, 3.0 - 1.5 / 2.25],
        [1.0, 4.0],
        [2.0, 3.0 - 3.0 / 2.25],
        [2.0, 4.0],
    ];
    assert_eq!(got.len(), 4, "{got:?}");
    for (p, q) in got.iter().zip(&want) {
        assert!(distance(*p, *q) < 1e-12, "{p:?} vs {q:?}");
    }
    // A box corner touching a polygon vertex; a region slightly off within tolerance.
    assert_eq!(
        box_crossings(&UPPER, &[2.0, 3.0, 0.0, 1.0], tol),
        vec![[2.0, 1.0]]
    );
    assert_eq!(
        box_crossings(&UPPER, &[1.0, 2.0, 2.0 + 1e-10, 2.0 + 1e-10], tol),
        vec![[1.0, 2.0], [2.0, 2.0]]
    );
}

/// Meshes the convex `polygon` (of size `scale`) at hmax = 2 `scale` / `divisions`, checks the
/// mesh, and returns its smallest angle, the polygon's smallest input angle (degrees) and the
/// boundary edge-length ratio.  The boundary discretisation is fixed (rule 1), so small input
/// angles and abrupt changes of boundary edge length limit the angles there (measured over 3000
/// cases: ≥ 20.1° whenever input ≥ 30° and ratio ≤ 2; ≥ 0.90 min(input, 20°) / ratio always).
/// Two cases the random search found under 20° before skinny triangles whose circumcentre
/// encroaches a boundary edge were mended are kept below (17.3° and 19.8°).
fn mesh_convex(polygon: &[Point], scale: f64, divisions: f64) -> (f64, f64, f64) {
    let hmax = 2.0 * scale / divisions;
    let g = BodyGeometry {
        tol: 1e-9 * scale,
        ..body(polygon, hmax, &[])
    };
    let mesh = mesh_body(&g, &MeshLimits::default()).unwrap();
    let angle = check_mesh(&mesh, polygon, hmax);
    (angle, input_angle_deg(polygon), boundary_ratio(&mesh))
}

/// The case `random_convex_polygons_mesh_validly` found on 2026-11-28 (a CI run; the property
/// held on every earlier run): a hexagon with input angles ≥ 64° and a boundary ratio of 1.91,
/// about one hmax thick, so no seed fits.  It meshed with a smallest angle of 17.3°: spade left
/// the fan triangle from a top boundary node to the short boundary edge at the right end
/// because its circumcentre encroaches the top boundary edge (kept, so not split), and halving
/// its two long sides kept the angle.  The circumcentre is now inserted (every triangle it
/// makes keeps 20°).
#[test]
fn a_convex_hexagon_the_random_search_found_keeps_twenty_degrees() {
    keeps_twenty_degrees(
        [
            5.522927295356044,
            0.2757035875442457,
            5.849843545635097,
            6.109817994662912,
            3.7809429247180373,
            2.955306650009249,
        ],
        0.4553399640296236,
        4.4879675573028255,
    );
}

/// A pentagon the random search found (50 000 cases, before the mend above) at 19.8° (input
/// 54.7°, boundary ratio 1.89): the same cause, a skinny triangle with its apex on the boundary
/// whose circumcentre encroaches a boundary edge (0.76 of its diametral radius from its middle).
#[test]
fn a_convex_pentagon_the_random_search_found_keeps_twenty_degrees() {
    keeps_twenty_degrees(
        [
            5.878878720330749,
            0.5445186783365117,
            1.1761214118763792,
            4.857155185744216,
            0.7983836492445485,
        ],
        0.3156561006658307,
        4.715591469475588,
    );
}

/// Meshes the convex polygon the random search builds from `angles` (on an ellipse of
/// `aspect`, size 1e-3, at `divisions`) and asserts the property's 20° where it applies.
fn keeps_twenty_degrees<const N: usize>(mut angles: [f64; N], aspect: f64, divisions: f64) {
    angles.sort_by(f64::total_cmp);
    let scale = 0.001;
    let polygon: Vec<Point> = angles
        .iter()
        .map(|t| [scale * t.cos(), scale * aspect * t.sin()])
        .collect();
    let (angle, input, ratio) = mesh_convex(&polygon, scale, divisions);
    assert!(
        input >= 30.0 && ratio <= 2.0,
        "test construction: input {input}, ratio {ratio}"
    );
    assert!(
        angle >= 20.0,
        "min angle {angle} (input {input}, ratio {ratio})"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn random_convex_polygons_mesh_validly(
        angles in prop::collection::vec(0.0..std::f64::consts::TAU, 3..9),
        aspect in 0.3..1.0f64,
        scale in prop::sample::select(vec![1e-3, 1.0, 1e3]),
        offset in (-10.0..10.0f64, -10.0..10.0f64),
        divisions in 3.0..25.0f64,
    ) {
        let mut angles = angles;
        angles.sort_by(f64::total_cmp);
        angles.dedup_by(|a, b| (*a - *b).abs() < 0.05);
        prop_assume!(angles.len() >= 3);
        let polygon: Vec<Point> = angles
            .iter()
            .map(|t| [scale * (offset.0 + t.cos()), scale * (offset.1 + aspect * t.sin())])
            .collect();
        prop_assume!(signed_area(&polygon) > 0.05 * scale * scale);
        let (angle, input, ratio) = mesh_convex(&polygon, scale, divisions);
        if input >= 30.0 && ratio <= 2.0 {
            prop_assert!(angle >= 20.0, "min angle {} (input {}, ratio {})", angle, input, ratio);
        }
        prop_assert!(angle >= 0.8 * input.min(20.0) / ratio, "min angle {} (input {}, ratio {})", angle, input, ratio);
    }
}

/// The Hertz cap of `fixtures/accuracy/hertz.toml` (arc given every 0.001 near the contact,
/// every 0.02 beyond) meshed at hmax 0.01 and 0.005: the long-edge splits cascade for 241
/// rounds at 0.01, past the 64 the mesher first allowed, and the body was refused ("refinement
/// did not finish") though a valid mesh exists.  Checked against geometry only: the polygon's
/// area, every edge ≤ hmax, and the angle bound — 20° except next to boundary edges much shorter
/// than their neighbours (the spacing jumps 20× where the fine arc begins: the mesher's
/// documented limit), so 15° is asked.
#[test]
fn a_boundary_ten_times_finer_than_hmax_meshes() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/accuracy/hertz.toml");
    let scene = signorini_core::scene::Scene::from_path(&path).unwrap();
    let cap = &scene.bodies[scene.body_index("cap").unwrap()];
    for hmax in [0.01, 0.005] {
        let mesh = p1(&cap.polygon, hmax, &[]);
        let area = signed_area(&cap.polygon);
        assert!((mesh.area() - area).abs() < 1e-9 * area);
        assert!(mesh.max_edge() <= hmax * (1.0 + 1e-9));
        assert!(mesh.min_angle_deg() >= 15.0, "{}", mesh.min_angle_deg());
    }
}
