//! Meshing speed (run with `cargo test --release -p signorini-core --test mesh_timing -- --ignored --nocapture`).

#![allow(clippy::unwrap_used)] // tests may unwrap

use std::time::Instant;

use signorini_core::mesh::{mesh_body, BodyGeometry, ElementKind, MeshLimits};

#[test]
#[ignore = "timing; run in release"]
fn p1_timings() {
    let upper = [[0.0, 1.0], [2.0, 1.0], [2.0, 2.0], [0.0, 2.0]];
    let wedge = [
        [0.0, 3.0],
        [2.25, 1.5],
        [2.75, 1.5],
        [5.0, 3.0],
        [5.0, 4.0],
        [0.0, 4.0],
    ];
    for (name, polygon) in [("upper", &upper[..]), ("wedge", &wedge[..])] {
        let area = signorini_core::geometry::signed_area(polygon).abs();
        for target in [1e4, 1e5, 1e6] {
            // About area / (0.35 hmax²) triangles.
            let hmax = (area / (0.35 * target)).sqrt();
            let body = BodyGeometry {
                polygon,
                hmax,
                element: ElementKind::P1,
                breakpoints: &[[1.0, 1.0], [1.0, 2.0]],
                refine: &[],
                tol: 1e-9,
            };
            let start = Instant::now();
            let mesh = mesh_body(&body, &MeshLimits::default()).unwrap();
            let seconds = start.elapsed().as_secs_f64();
            println!(
                "{name}: hmax {hmax:.5}: {} triangles, {} nodes, {seconds:.3} s, max edge / hmax {:.4}, min angle {:.2}°",
                mesh.cells.len(),
                mesh.nodes.len(),
                mesh.max_edge() / hmax,
                mesh.min_angle_deg()
            );
        }
    }
}

#[test]
#[ignore = "diagnostic"]
fn contact_box_breakpoints() {
    use signorini_core::mesh::box_crossings;
    let upper = [[0.0, 1.0], [2.0, 1.0], [2.0, 2.0], [0.0, 2.0]];
    for hmax in [0.2, 0.08, 0.02] {
        let mut breaks = box_crossings(&upper, &[1.0, 2.0, 0.99, 1.01], 1e-9);
        breaks.push([1.0, 1.0]);
        let body = BodyGeometry {
            polygon: &upper,
            hmax,
            element: ElementKind::P1,
            breakpoints: &breaks,
            refine: &[],
            tol: 1e-9,
        };
        let mesh = mesh_body(&body, &MeshLimits::default()).unwrap();
        println!(
            "hmax {hmax}: {} triangles, min angle {:.2}",
            mesh.cells.len(),
            mesh.min_angle_deg()
        );
    }
}

#[test]
#[ignore = "diagnostic"]
fn nasty_polygons() {
    let sliver = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.01]];
    let comb: Vec<[f64; 2]> = {
        let mut v = vec![[0.0, 0.0], [1.0, 0.0]];
        for i in (0..10).rev() {
            let x = i as f64 * 0.1;
            v.push([x + 0.1, 1.0]);
            v.push([x + 0.05, 1.0]);
            v.push([x + 0.05, 0.2]);
            v.push([x, 0.2]);
        }
        v.pop();
        v.push([0.0, 1.0]);
        v
    };
    let star: Vec<[f64; 2]> = (0..20)
        .map(|i| {
            let t = i as f64 * std::f64::consts::PI / 10.0;
            let r = if i % 2 == 0 { 1.0 } else { 0.2 };
            [r * t.cos(), r * t.sin()]
        })
        .collect();
    for (name, polygon) in [
        ("sliver", &sliver[..]),
        ("comb", &comb[..]),
        ("star", &star[..]),
    ] {
        for hmax in [0.3, 0.05, 0.01, 0.003] {
            let body = BodyGeometry {
                polygon,
                hmax,
                element: ElementKind::P1,
                breakpoints: &[],
                refine: &[],
                tol: 1e-9,
            };
            let start = Instant::now();
            match mesh_body(&body, &MeshLimits::default()) {
                Ok(mesh) => println!(
                    "{name} {hmax}: {} triangles, {:.3} s, max edge/h {:.4}, min angle {:.2}, area {}",
                    mesh.cells.len(),
                    start.elapsed().as_secs_f64(),
                    mesh.max_edge() / hmax,
                    mesh.min_angle_deg(),
                    mesh.area()
                ),
                Err(e) => println!("{name} {hmax}: error {e}"),
            }
        }
    }
}
