//! Graded meshes (`[[body.refine]]`).
use signorini_core::mesh::*;
use std::time::Instant;

#[test]
fn explore() {
    let block = [[0.0, 0.0], [0.8, 0.0], [0.8, 0.4], [0.0, 0.4]];
    let fine = [Refinement { region: [0.35, 0.45, 0.38, 0.4], hmax: 0.0025 }];
    for el in [ElementKind::P1, ElementKind::Q1] {
        let g = BodyGeometry { polygon: &block, hmax: 0.05, element: el, breakpoints: &[[0.35,0.4],[0.45,0.4]], refine: &fine, tol: 1e-9 };
        let t = Instant::now();
        let m = mesh_body(&g, &MeshLimits::default()).unwrap();
        println!("{el:?} {:?} cells {} nodes {} est {} estn {} minangle {} area {}", t.elapsed(), m.cells.len(), m.nodes.len(),
            estimate_elements_refined(&block, 0.05, &fine, el), estimate_nodes_refined(&block, 0.05, &fine, el), m.min_angle_deg(), m.area());
    }
}
