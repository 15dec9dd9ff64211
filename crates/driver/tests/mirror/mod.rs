//! Two equal cylinders, mirror images about their contact line, with exactly mirrored meshes:
//! the Cattaneo–Mindlin scene of `scripts/hertz-scene.py --mirror` built at test time, so that
//! no generated mesh is committed.
//!
//! Each body is a W × D slab whose contact face is an arc of radius R (polygon vertices every
//! `arc` for |x − cx| ≤ 0.15, every 0.02 beyond, as the script's defaults), `upper` above the
//! line y = D, `lower` its mirror image below.  The mesher need not mesh a mirrored polygon as
//! the mirror image of the original's mesh, and that difference couples the normal and
//! tangential problems (BENCHMARKS.md, Cattaneo: a tangential traction of 2.2 % of μp₀ after the
//! press alone with the polygons meshed separately).  So `lower` is meshed by the library's own
//! mesher (`signorini_core::model::mesh_scene`, the same mesh `solve` would make of the polygon
//! scene), `upper` is its exact mirror image, and both are written as MSH 4.1 files that the
//! scene names with `mesh = …`.
#![allow(dead_code)]

use signorini_core::mesh::{Cells, Mesh, MeshLimits};
use signorini_core::model::mesh_scene;
use signorini_core::scene::Scene;
use std::fmt::Write as _;
use std::path::Path;

/// Slab width W and depth D (the script's `--block-width`, `--block-depth`).
pub const WIDTH: f64 = 1.6;
/// The contact line y = D, the mirror.
pub const BASE: f64 = 0.8;
/// The contact's centre x.
pub const CENTRE: f64 = 0.8;

/// The scene's knobs (`hertz-scene.py --mirror --graded --cattaneo MU` options).
#[derive(Debug, Clone)]
pub struct Params {
    /// Cylinder radius R (R* = R/2).
    pub radius: f64,
    /// Bodies' hmax.
    pub hmax: f64,
    /// Refine box half-width (the box is [cx − zone, cx + zone] × [D, D + zone] and its mirror).
    pub zone: f64,
    /// Refine hmax: the contact zone's h.
    pub zone_hmax: f64,
    /// Arc polygon spacing for |x − cx| ≤ 0.15.
    pub arc: f64,
    /// Downward move of the upper slab's top (`press`).
    pub press: f64,
    /// Sideways move of the top (`shift`).
    pub shift: f64,
    /// Increments of the shift step.
    pub increments: usize,
    /// Coulomb μ.
    pub mu: f64,
    /// `mortar` or `node-to-segment`.
    pub formulation: &'static str,
}

/// The arc's angles from −φ₀ to φ₀, fine where |R sin φ| ≤ 0.15 (`arc_angles` of the script).
fn arc_angles(r: f64, phi0: f64, ds_fine: f64) -> Vec<f64> {
    let (fine_width, ds_coarse) = (0.15_f64, 0.02);
    let phi_f = (fine_width / r).min(1.0).asin();
    let n_f = ((2.0 * phi_f * r / ds_fine).ceil() as usize).max(1);
    let n_c = (((phi0 - phi_f) * r / ds_coarse).ceil() as usize).max(1);
    let mut out: Vec<f64> = (0..n_c)
        .map(|i| -phi0 + (phi0 - phi_f) * i as f64 / n_c as f64)
        .collect();
    out.extend((0..=n_f).map(|i| -phi_f + 2.0 * phi_f * i as f64 / n_f as f64));
    out.extend((1..=n_c).map(|i| phi_f + (phi0 - phi_f) * i as f64 / n_c as f64));
    out
}

/// The lower slab's polygon, counter-clockwise: flat bottom y = 0, the arc's mirror image on top.
fn lower_polygon(p: &Params) -> Vec<[f64; 2]> {
    let r = p.radius;
    let phi0 = (WIDTH / (2.0 * r)).min(1.0).asin();
    let mut arc: Vec<[f64; 2]> = arc_angles(r, phi0, p.arc)
        .into_iter()
        .map(|t| [CENTRE + r * t.sin(), BASE - (r - r * t.cos())])
        .collect();
    let n = arc.len();
    arc[0][0] = 0.0;
    arc[n - 1][0] = WIDTH;
    // The arc from x = W back to x = 0 keeps the body (below it) on the left.
    let mut polygon = vec![[0.0, 0.0], [WIDTH, 0.0]];
    polygon.extend(arc.into_iter().rev());
    polygon
}

/// A coordinate as TOML, exactly (Rust's shortest round-trip form).
fn num(v: f64) -> String {
    format!("{v:?}")
}

/// The polygon scene whose `lower` body is meshed as `solve` would mesh it: its refine box, its
/// support and the pair's box break its boundary (the `upper` polygon, the mirror image, is
/// there for the pair; its corners off the lower boundary do not touch the lower mesh).
fn polygon_scene(p: &Params) -> String {
    let text = |poly: &[[f64; 2]]| -> String {
        let list: Vec<String> = poly
            .iter()
            .map(|[x, y]| format!("[{}, {}]", num(*x), num(*y)))
            .collect();
        list.join(", ")
    };
    let lower = lower_polygon(p);
    let upper: Vec<[f64; 2]> = lower.iter().rev().map(|&q| mirror(q)).collect();
    let z = p.zone;
    format!(
        "[[body]]\nname = \"lower\"\npolygon = [{}]\nhmax = {}\nyoung = 1.0\npoisson = 0.3\n\
         [[body.refine]]\nregion = [{}, {}, {}, {}]\nhmax = {}\n\n\
         [[body]]\nname = \"upper\"\npolygon = [{}]\nhmax = 0.2\nyoung = 1.0\npoisson = 0.3\n\n\
         [[dirichlet]]\nbody = \"lower\"\nregion = [0.0, {WIDTH:?}, 0.0, 0.0]\n\n{}",
        text(&lower),
        num(p.hmax),
        num(CENTRE - z),
        num(CENTRE + z),
        num(BASE - z),
        num(BASE),
        num(p.zone_hmax),
        text(&upper),
        contact(p),
    )
}

/// The reflection about the contact line y = D.
fn mirror([x, y]: [f64; 2]) -> [f64; 2] {
    [x, 2.0 * BASE - y]
}

/// The pair (`lower` the slave, as in `hertz-scene.py --mirror`) with Coulomb μ.
fn contact(p: &Params) -> String {
    format!(
        "[[contact]]\nbodies = [\"upper\", \"lower\"]\nregion = [{}, {}, {}, {}]\n\
         slave = \"lower\"\nformulation = \"{}\"\nfriction = {}\n",
        num(CENTRE - 0.2),
        num(CENTRE + 0.2),
        num(BASE - 0.01),
        num(BASE + 0.01),
        p.formulation,
        num(p.mu)
    )
}

/// MSH 4.1 ASCII text of `mesh` (triangles) with every node mapped by `f` and, when `flip`, every
/// triangle's order reversed (a mirror image stays counter-clockwise).
fn msh(mesh: &Mesh, f: impl Fn([f64; 2]) -> [f64; 2], flip: bool) -> String {
    let Cells::Triangles(tris) = &mesh.cells else {
        panic!("P1 mesh expected")
    };
    let (n, m) = (mesh.nodes.len(), tris.len());
    let mut s = format!("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 {n} 1 {n}\n2 1 0 {n}\n");
    for tag in 1..=n {
        writeln!(s, "{tag}").unwrap();
    }
    for &node in &mesh.nodes {
        let [x, y] = f(node);
        writeln!(s, "{x:?} {y:?} 0").unwrap();
    }
    write!(s, "$EndNodes\n$Elements\n1 {m} 1 {m}\n2 1 2 {m}\n").unwrap();
    for (i, t) in tris.iter().enumerate() {
        let [a, b, c] = if flip { [t[2], t[1], t[0]] } else { *t };
        writeln!(s, "{} {} {} {}", i + 1, a + 1, b + 1, c + 1).unwrap();
    }
    s + "$EndElements\n"
}

/// Meshes the lower slab, writes `lower.msh` and its mirror image `upper.msh` into `dir` and
/// returns the scene (press, then shift in `increments` increments) naming them; also the
/// number of nodes per body.
pub fn write_scene(p: &Params, dir: &Path) -> (String, usize) {
    let scene = Scene::from_toml(&polygon_scene(p)).unwrap();
    let meshes = mesh_scene(&scene, &MeshLimits::default()).unwrap();
    let lower = &meshes[0];
    std::fs::write(dir.join("lower.msh"), msh(lower, |q| q, false)).unwrap();
    std::fs::write(dir.join("upper.msh"), msh(lower, mirror, true)).unwrap();
    let top = format!("region = [0.0, {WIDTH:?}, 1.6, 1.6]");
    let text = format!(
        "title = \"Cattaneo-Mindlin, two equal cylinders pressed then shifted\"\n\n\
         [[body]]\nname = \"upper\"\nmesh = \"upper.msh\"\nyoung = 1.0\npoisson = 0.3\n\n\
         [[body]]\nname = \"lower\"\nmesh = \"lower.msh\"\nyoung = 1.0\npoisson = 0.3\n\n\
         [[dirichlet]]\nbody = \"lower\"\nregion = [0.0, {WIDTH:?}, 0.0, 0.0]\n\n\
         [[dirichlet]]\nname = \"press\"\nbody = \"upper\"\n{top}\ncomponents = [\"y\"]\n\
         value = [0.0, {}]\n\n\
         [[dirichlet]]\nname = \"shift\"\nbody = \"upper\"\n{top}\ncomponents = [\"x\"]\n\
         value = [{}, 0.0]\n\n{}\n\
         [[step]]\nloads = {{ press = 1.0 }}\n\n\
         [[step]]\nloads = {{ press = 1.0, shift = 1.0 }}\nincrements = {}\n",
        num(-p.press),
        num(p.shift),
        contact(p),
        p.increments
    );
    (text, lower.nodes.len())
}
