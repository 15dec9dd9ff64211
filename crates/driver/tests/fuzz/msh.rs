//! Gmsh files for the generator: a rectangle cut into a grid, written as MSH 4.1 ASCII the way
//! Gmsh writes one (`$MeshFormat`, `$Entities`, `$Nodes`, `$Elements`; docs/scene.md, "Bodies
//! from Gmsh meshes", says what the reader accepts).  No physical group: Gmsh then saves every
//! element, and the scene's boxes (`region`) select the boundary.

use std::fmt::Write;

/// The rectangle `r = [x0, x1, y0, y1]` cut into `n = [nx, ny]` cells: linear quadrilaterals
/// (Gmsh type 3) when `quads`, else two linear triangles (type 2) per cell; every element
/// counter-clockwise, or every one clockwise when `clockwise` (a surface whose normal points
/// along −z, which the reader turns around).
pub fn grid(r: [f64; 4], n: [usize; 2], quads: bool, clockwise: bool) -> String {
    let [x0, x1, y0, y1] = r;
    let [nx, ny] = n;
    // Node (i, j) has tag 1 + i + j (nx + 1); the last column and row sit exactly on x1 and y1.
    let coord = |lo: f64, hi: f64, k: usize, of: usize| {
        if k == of {
            hi
        } else {
            lo + (hi - lo) * k as f64 / of as f64
        }
    };
    let tag = |i: usize, j: usize| 1 + i + j * (nx + 1);
    let nodes = (nx + 1) * (ny + 1);
    let mut elements: Vec<Vec<usize>> = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let [a, b, c, d] = [tag(i, j), tag(i + 1, j), tag(i + 1, j + 1), tag(i, j + 1)];
            if quads {
                elements.push(vec![a, b, c, d]);
            } else {
                elements.push(vec![a, b, c]);
                elements.push(vec![a, c, d]);
            }
        }
    }
    if clockwise {
        elements.iter_mut().for_each(|e| e.reverse());
    }
    let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    // One surface entity (tag 1, its bounding box, no physical tag, no bounding curve).
    let _ = write!(
        s,
        "$Entities\n0 0 1 0\n1 {x0:?} {y0:?} 0 {x1:?} {y1:?} 0 0 0\n$EndEntities\n"
    );
    let _ = write!(s, "$Nodes\n1 {nodes} 1 {nodes}\n2 1 0 {nodes}\n");
    for t in 1..=nodes {
        let _ = writeln!(s, "{t}");
    }
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (coord(x0, x1, i, nx), coord(y0, y1, j, ny));
            let _ = writeln!(s, "{x:?} {y:?} 0");
        }
    }
    let count = elements.len();
    let kind = if quads { 3 } else { 2 };
    let _ = write!(
        s,
        "$EndNodes\n$Elements\n1 {count} 1 {count}\n2 1 {kind} {count}\n"
    );
    for (k, e) in elements.iter().enumerate() {
        let list: Vec<String> = e.iter().map(usize::to_string).collect();
        let _ = writeln!(s, "{} {}", k + 1, list.join(" "));
    }
    s.push_str("$EndElements\n");
    s
}
