use signorini_core::mesh::*;
use std::time::Instant;

#[test]
#[ignore]
fn explore() {
    let upper = [[0.0, 1.0], [2.0, 1.0], [2.0, 2.0], [0.0, 2.0]];
    let wedge = [
        [0.0, 3.0],
        [2.25, 1.5],
        [2.75, 1.5],
        [5.0, 3.0],
        [5.0, 4.0],
        [0.0, 4.0],
    ];
    for (name, poly) in [("upper", &upper[..]), ("wedge", &wedge[..])] {
        for h in [0.2, 0.08, 0.02, 0.005, 0.002] {
            let g = BodyGeometry {
                polygon: poly,
                hmax: h,
                element: ElementKind::P1,
                breakpoints: &[[1.0, 1.0], [1.0, 2.0]],
                tol: 1e-9,
            };
            let t = Instant::now();
            let m = mesh_body(&g, &MeshLimits::default()).unwrap();
            let dt = t.elapsed().as_secs_f64();
            let area = m.area();
            println!("{name} h={h} tri={} nodes={} est={} maxedge/h={:.4} minangle={:.2} area={} t={:.3}s  A/(N h^2)={:.3}",
                m.cells.len(), m.nodes.len(), estimate_elements(poly, h, ElementKind::P1), m.max_edge()/h, m.min_angle_deg(), area, dt, area/(m.cells.len() as f64*h*h));
        }
    }
}
