//! Gmsh meshes (issue 11, item 1): small MSH 4.1 files written here, read through `mshio`;
//! every bad mesh is refused with an error naming the file and the problem, never a panic; the
//! physical groups select Dirichlet nodes, Neumann edges and contact candidates.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use signorini_core::contact::contact_rows;
use signorini_core::effects::Effects;
use signorini_core::fem::Dofs;
use signorini_core::geometry::signed_area;
use signorini_core::mesh::gmsh::{parse_msh, GmshProblem};
use signorini_core::mesh::Cells;
use signorini_core::mesh::MeshLimits;
use signorini_core::model::mesh_scene;
use signorini_core::scene::{Scene, SceneError};

/// An element block: entity dimension, entity tag, Gmsh element type, elements (tag, node tags).
type Block = (i32, i32, i32, Vec<(u64, Vec<u64>)>);

/// An ASCII MSH 4.1 file: nodes `(tag, [x, y, z])` in one block, element blocks, and physical
/// groups `(dim, tag, name)` attached to the entity of the same dimension and tag.
fn msh(nodes: &[(u64, [f64; 3])], blocks: &[Block], groups: &[(i32, i32, &str)]) -> String {
    let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    s += &format!("$PhysicalNames\n{}\n", groups.len());
    for (d, t, n) in groups {
        s += &format!("{d} {t} \"{n}\"\n");
    }
    s += "$EndPhysicalNames\n";
    // Entities: every (dim, tag) used by a block, with the physical tag of the same number.
    let mut ents: Vec<(i32, i32)> = blocks.iter().map(|b| (b.0, b.1)).collect();
    ents.sort();
    ents.dedup();
    let count = |d: i32| ents.iter().filter(|e| e.0 == d).count();
    s += &format!("$Entities\n{} {} {} 0\n", count(0), count(1), count(2));
    for &(d, t) in &ents {
        let phys: Vec<String> = groups
            .iter()
            .filter(|g| g.0 == d && g.1 == t)
            .map(|g| g.1.to_string())
            .collect();
        let p = format!("{} {}", phys.len(), phys.join(" "));
        if d == 0 {
            s += &format!("{t} 0 0 0 {p}\n");
        } else {
            s += &format!("{t} 0 0 0 1 1 0 {p} 0\n");
        }
    }
    s += "$EndEntities\n";
    let tags: Vec<u64> = nodes.iter().map(|n| n.0).collect();
    s += &format!(
        "$Nodes\n1 {} {} {}\n2 1 0 {}\n",
        nodes.len(),
        tags.iter().min().unwrap(),
        tags.iter().max().unwrap(),
        nodes.len()
    );
    for t in &tags {
        s += &format!("{t}\n");
    }
    for (_, c) in nodes {
        s += &format!("{} {} {}\n", c[0], c[1], c[2]);
    }
    s += "$EndNodes\n";
    let all: Vec<u64> = blocks
        .iter()
        .flat_map(|b| b.3.iter().map(|e| e.0))
        .collect();
    s += &format!(
        "$Elements\n{} {} {} {}\n",
        blocks.len(),
        all.len(),
        all.iter().min().unwrap(),
        all.iter().max().unwrap()
    );
    for (d, t, ty, els) in blocks {
        s += &format!("{d} {t} {ty} {}\n", els.len());
        for (tag, n) in els {
            let n: Vec<String> = n.iter().map(|x| x.to_string()).collect();
            s += &format!("{tag} {}\n", n.join(" "));
        }
    }
    s += "$EndElements\n";
    s
}

/// The unit square: corners 1–4 counter-clockwise from (0, 0), centre 5; four triangles.
fn square_nodes() -> Vec<(u64, [f64; 3])> {
    vec![
        (1, [0.0, 0.0, 0.0]),
        (2, [1.0, 0.0, 0.0]),
        (3, [1.0, 1.0, 0.0]),
        (4, [0.0, 1.0, 0.0]),
        (5, [0.5, 0.5, 0.0]),
    ]
}

fn square_triangles() -> Vec<(u64, Vec<u64>)> {
    vec![
        (10, vec![1, 2, 5]),
        (11, vec![2, 3, 5]),
        (12, vec![3, 4, 5]),
        (13, vec![4, 1, 5]),
    ]
}

/// Lines "bottom" (curve 1) and "top" (curve 2), the surface "body" (surface 1).
fn square_blocks(triangles: Vec<(u64, Vec<u64>)>) -> Vec<Block> {
    vec![
        (1, 1, 1, vec![(1, vec![1, 2])]),
        (1, 2, 1, vec![(2, vec![3, 4])]),
        (2, 1, 2, triangles),
    ]
}

const GROUPS: [(i32, i32, &str); 3] = [(1, 1, "bottom"), (1, 2, "top"), (2, 1, "body")];

fn square() -> String {
    msh(&square_nodes(), &square_blocks(square_triangles()), &GROUPS)
}

/// The error of parsing `text`, checked to name the file.
fn refused(text: &str) -> (GmshProblem, String) {
    let e = parse_msh(text.as_bytes(), "part.msh").unwrap_err();
    let message = e.to_string();
    assert!(message.contains("part.msh"), "{message}");
    (e.problem, message)
}

#[test]
fn a_square_is_read_with_its_boundary_and_groups() {
    let m = parse_msh(square().as_bytes(), "square.msh").unwrap();
    assert_eq!(m.mesh.nodes.len(), 5);
    assert_eq!(m.mesh.cells.len(), 4);
    assert!(matches!(m.mesh.cells, Cells::Triangles(_)));
    // The boundary: the four sides, one counter-clockwise loop of area 1.
    assert_eq!(m.mesh.boundary.len(), 4);
    assert!((signed_area(&m.outline) - 1.0).abs() < 1e-15);
    for w in m.mesh.boundary.windows(2) {
        assert_eq!(w[0][1], w[1][0]);
    }
    // Nodes are numbered in tag order: tag t is node t − 1.
    let bottom = m.group("bottom").unwrap();
    assert_eq!(bottom.nodes, vec![0, 1]);
    assert_eq!(bottom.edges, vec![[0, 1]]);
    let top = m.group("top").unwrap();
    assert_eq!(top.edges, vec![[2, 3]]);
    // The surface group holds every node and every boundary edge.
    let body = m.group("body").unwrap();
    assert_eq!(body.nodes.len(), 5);
    assert_eq!(body.edges.len(), 4);
}

#[test]
fn clockwise_elements_are_reoriented_all_together() {
    let cw: Vec<_> = square_triangles()
        .into_iter()
        .map(|(t, mut n)| {
            n.reverse();
            (t, n)
        })
        .collect();
    let m = parse_msh(
        msh(&square_nodes(), &square_blocks(cw), &GROUPS).as_bytes(),
        "cw.msh",
    )
    .unwrap();
    assert!((m.mesh.area() - 1.0).abs() < 1e-15);
    assert!((signed_area(&m.outline) - 1.0).abs() < 1e-15);
}

#[test]
fn quadrilaterals_give_q1() {
    let blocks = vec![
        (1, 1, 1, vec![(1, vec![1, 2])]),
        (2, 1, 3, vec![(10, vec![1, 2, 3, 4])]),
    ];
    let nodes = &square_nodes()[..4];
    let m = parse_msh(msh(nodes, &blocks, &[(1, 1, "bottom")]).as_bytes(), "q.msh").unwrap();
    assert!(matches!(m.mesh.cells, Cells::Quads(_)));
    assert_eq!(m.mesh.boundary.len(), 4);
}

#[test]
fn an_inverted_element_is_refused() {
    let mut t = square_triangles();
    t[1].1 = vec![2, 5, 3];
    let (p, message) = refused(&msh(&square_nodes(), &square_blocks(t), &GROUPS));
    assert!(
        matches!(p, GmshProblem::Inverted { element: 11, .. }),
        "{p:?}"
    );
    assert!(message.contains("element 11 is inverted"), "{message}");
}

#[test]
fn a_degenerate_element_is_refused() {
    // Node 6 on the bottom side: triangle 1-2-6 has zero area.
    let mut nodes = square_nodes();
    nodes.push((6, [0.5, 0.0, 0.0]));
    let mut t = square_triangles();
    t.push((14, vec![1, 2, 6]));
    let (p, message) = refused(&msh(&nodes, &square_blocks(t), &GROUPS));
    assert!(
        matches!(p, GmshProblem::Degenerate { element: 14, .. }),
        "{p:?}"
    );
    assert!(message.contains("degenerate"), "{message}");
}

#[test]
fn quadratic_triangles_are_refused_by_name() {
    let blocks = vec![(2, 1, 9, vec![(1, vec![1, 2, 3, 4, 5, 5])])];
    let (p, message) = refused(&msh(&square_nodes(), &blocks, &[]));
    assert!(
        matches!(p, GmshProblem::UnsupportedElement { code: 9, .. }),
        "{p:?}"
    );
    assert!(
        message.contains("Tri6") && message.contains("type 9"),
        "{message}"
    );
}

#[test]
fn non_planar_nodes_are_refused() {
    let mut nodes = square_nodes();
    nodes[4].1[2] = 0.1;
    let (p, message) = refused(&msh(&nodes, &square_blocks(square_triangles()), &GROUPS));
    assert!(matches!(p, GmshProblem::NotPlanar { .. }), "{p:?}");
    assert!(message.contains("not planar"), "{message}");
}

#[test]
fn a_constant_nonzero_z_is_accepted() {
    let mut nodes = square_nodes();
    for n in &mut nodes {
        n.1[2] = 2.5;
    }
    parse_msh(
        msh(&nodes, &square_blocks(square_triangles()), &GROUPS).as_bytes(),
        "z.msh",
    )
    .unwrap();
}

#[test]
fn duplicate_nodes_are_refused() {
    // Node 6 repeats the centre, used by one triangle: the mesh is not conforming there.
    let mut nodes = square_nodes();
    nodes.push((6, [0.5, 0.5, 0.0]));
    let mut t = square_triangles();
    t[3].1 = vec![4, 1, 6];
    let (p, message) = refused(&msh(&nodes, &square_blocks(t), &GROUPS));
    assert!(
        matches!(p, GmshProblem::DuplicateNodes { a: 5, b: 6, .. }),
        "{p:?}"
    );
    assert!(message.contains("nodes 5 and 6 coincide"), "{message}");
}

#[test]
fn a_file_without_surface_elements_is_refused() {
    let blocks = vec![(1, 1, 1, vec![(1, vec![1, 2])])];
    let (p, message) = refused(&msh(&square_nodes(), &blocks, &[(1, 1, "bottom")]));
    assert_eq!(p, GmshProblem::NoElements);
    assert!(message.contains("no 2-D element"), "{message}");
}

#[test]
fn mixed_triangles_and_quads_are_refused() {
    let mut blocks = square_blocks(square_triangles());
    blocks.push((2, 2, 3, vec![(20, vec![1, 2, 3, 4])]));
    let (p, _) = refused(&msh(&square_nodes(), &blocks, &GROUPS));
    assert!(
        matches!(
            p,
            GmshProblem::MixedElements {
                triangles: 4,
                quads: 1
            }
        ),
        "{p:?}"
    );
}

#[test]
fn two_pieces_are_refused() {
    let mut nodes = square_nodes();
    nodes.extend([
        (6, [3.0, 0.0, 0.0]),
        (7, [4.0, 0.0, 0.0]),
        (8, [3.0, 1.0, 0.0]),
    ]);
    let mut t = square_triangles();
    t.push((14, vec![6, 7, 8]));
    let (p, message) = refused(&msh(&nodes, &square_blocks(t), &GROUPS));
    assert!(matches!(p, GmshProblem::Boundary { loops: 2, .. }), "{p:?}");
    assert!(message.contains("2 closed loop"), "{message}");
}

#[test]
fn overlapping_elements_are_refused() {
    // A fifth triangle over the first: edge 1–2 is used twice on the same side.
    let mut t = square_triangles();
    t.push((14, vec![1, 2, 5]));
    let (p, message) = refused(&msh(&square_nodes(), &square_blocks(t), &GROUPS));
    assert!(matches!(p, GmshProblem::NonManifold { .. }), "{p:?}");
    assert!(message.contains("overlapping"), "{message}");
}

#[test]
fn contact_groups_are_checked() {
    let dir = Dir::new("contact");
    let pair = |group: &str| {
        format!(
            "{SCENE}\n[[body]]\nname = \"base\"\npolygon = [[0, -1], [1, -1], [1, 0], [0, 0]]\n\
             hmax = 0.5\nyoung = 1.0\npoisson = 0.3\n[[dirichlet]]\nbody = \"base\"\n\
             region = [0, 1, -1, -1]\n[[contact]]\nbodies = [\"part\", \"base\"]\ngroup = {group:?}\n"
        )
    };
    // The mesh body has "bottom": accepted (the polygon body is not restricted).
    let scene = Scene::from_toml_in(&pair("bottom"), dir.path()).unwrap();
    assert_eq!(scene.contacts[0].group.as_deref(), Some("bottom"));
    // A group neither body has: the file and its groups are named.
    let e = scene_error(&pair("floor"), &dir);
    assert!(
        e.contains("\"floor\" is a physical group of neither body") && e.contains("square.msh"),
        "{e}"
    );
}

#[test]
fn a_contact_group_restricts_the_candidates() {
    // The square rests on a block below it; the square is the slave.  Its side on the block is
    // the group "bottom": without a group, or with "bottom", both bottom nodes get a row; with
    // "top" (the far side) the square has no candidate on the interface, so no row.
    let dir = Dir::new("candidates");
    let scene = |group: Option<&str>| {
        let line = group
            .map(|g| format!("group = {g:?}\n"))
            .unwrap_or_default();
        let text = format!(
            "[[body]]\nname = \"part\"\nmesh = \"square.msh\"\nyoung = 1.0\npoisson = 0.3\n\
             [[body]]\nname = \"base\"\npolygon = [[0, -1], [1, -1], [1, 0], [0, 0]]\n\
             hmax = 1.0\nyoung = 1.0\npoisson = 0.3\n[[dirichlet]]\nbody = \"base\"\n\
             region = [0, 1, -1, -1]\n[[contact]]\nbodies = [\"part\", \"base\"]\n\
             slave = \"part\"\n{line}"
        );
        Scene::from_toml_in(&text, dir.path()).unwrap()
    };
    let rows = |s: &Scene| {
        let meshes = mesh_scene(s, &MeshLimits::default()).unwrap();
        let contact = Effects::of(s).contact.unwrap();
        contact_rows(&contact.interfaces, &meshes, contact.tol).unwrap()[0]
            .rows
            .len()
    };
    assert_eq!(rows(&scene(None)), 2);
    assert_eq!(rows(&scene(Some("bottom"))), 2);
    assert_eq!(rows(&scene(Some("top"))), 0);
}

/// Mutated files (bytes overwritten, deterministic pseudo-random) are read or refused, never a
/// panic: a panic inside mshio is caught, and the checks after it index nothing unchecked.
#[test]
fn mutated_files_never_panic() {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let binary = std::fs::read(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/gmsh/cap-binary.msh"),
    )
    .unwrap();
    for (base, cases) in [(square().into_bytes(), 3000), (binary, 100)] {
        for _ in 0..cases {
            let mut bytes = base.clone();
            for _ in 0..1 + next() % 3 {
                let at = (next() % bytes.len() as u64) as usize;
                bytes[at] = b"0123456789.-e $\n"[(next() % 16) as usize];
            }
            let _ = parse_msh(&bytes, "mutated.msh");
        }
    }
}

#[test]
fn garbage_and_truncated_files_are_refused_without_panic() {
    for text in [
        "hello".to_string(),
        square()[..200].to_string(),
        square().replace("4.1 0 8", "2.2 0 8"),
        String::from_utf8_lossy(&[0xff; 64]).to_string(),
    ] {
        let (p, _) = refused(&text);
        assert!(matches!(p, GmshProblem::Parse(_)), "{p:?}");
    }
}

/// A scratch directory holding `square.msh`, removed on drop.
struct Dir(PathBuf);

impl Dir {
    fn new(name: &str) -> Self {
        let d = std::env::temp_dir().join(format!("signorini-gmsh-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(d.join("square.msh"), square()).unwrap();
        Dir(d)
    }
    fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for Dir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

const SCENE: &str = r#"
[[body]]
name = "part"
mesh = "square.msh"
young = 1.0
poisson = 0.3

[[dirichlet]]
body = "part"
group = "bottom"

[[neumann]]
body = "part"
group = "top"
traction = [0.0, -2.0]
"#;

fn scene_error(text: &str, dir: &Dir) -> String {
    let e = Scene::from_toml_in(text, dir.path()).unwrap_err();
    assert!(matches!(e, SceneError::Invalid { .. }), "{e:?}");
    e.to_string()
}

#[test]
fn groups_select_supports_and_loads() {
    let dir = Dir::new("groups");
    let scene = Scene::from_toml_in(SCENE, dir.path()).unwrap();
    let body = &scene.bodies[0];
    assert!(body.imported.is_some());
    // hmax of a mesh body is its longest element edge (a side of the square).
    assert!((body.hmax - 1.0).abs() < 1e-15);
    assert_eq!(scene.dirichlet[0].group.as_deref(), Some("bottom"));
    let meshes = mesh_scene(&scene, &MeshLimits::default()).unwrap();
    let dofs = Dofs::new(&[meshes[0].nodes.len()]);
    // Fixed: both components of nodes 0 and 1 (tags 1, 2 on the bottom line), nothing else.
    let effects = Effects::of(&scene);
    let mut fixed = vec![None; dofs.len()];
    let supports = effects.supports.as_ref().unwrap();
    supports.prescribe(&meshes, &dofs, &mut fixed).unwrap();
    let fixed_dofs: Vec<usize> = (0..fixed.len()).filter(|&i| fixed[i].is_some()).collect();
    let expected: Vec<usize> = [0, 1]
        .iter()
        .flat_map(|&n| [dofs.dof(0, n, 0), dofs.dof(0, n, 1)])
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    assert_eq!(fixed_dofs, expected);
    // Load: ty = −2 over the top side (length 1), half on each of its end nodes (tags 3, 4).
    let mut f = vec![0.0; dofs.len()];
    let tractions = effects.tractions.as_ref().unwrap();
    tractions.add_nodal(&meshes, &dofs, &mut f).unwrap();
    for n in 0..5 {
        let want = if n == 2 || n == 3 { -1.0 } else { 0.0 };
        assert!(
            (f[dofs.dof(0, n, 1)] - want).abs() < 1e-15,
            "node {n}: {}",
            f[dofs.dof(0, n, 1)]
        );
        assert_eq!(f[dofs.dof(0, n, 0)], 0.0);
    }
}

#[test]
fn scene_refusals_name_the_file_and_the_problem() {
    let dir = Dir::new("refusals");
    // A group the file does not define: the file and its groups are named.
    let e = scene_error(&SCENE.replace("\"bottom\"", "\"base\""), &dir);
    assert!(
        e.contains("\"base\"")
            && e.contains("square.msh")
            && e.contains("\"body\", \"bottom\", \"top\""),
        "{e}"
    );
    // polygon and mesh, neither, hmax or element with mesh, group and region together.
    let e = scene_error(
        &SCENE.replace(
            "young = 1.0",
            "polygon = [[0, 0], [1, 0], [1, 1]]\nyoung = 1.0",
        ),
        &dir,
    );
    assert!(
        e.contains("`mesh` cannot be combined with `polygon`"),
        "{e}"
    );
    let e = scene_error(&SCENE.replace("mesh = \"square.msh\"", ""), &dir);
    assert!(e.contains("`polygon` is missing"), "{e}");
    for key in ["hmax = 0.1", "element = \"p1\""] {
        let e = scene_error(
            &SCENE.replace("young = 1.0", &format!("{key}\nyoung = 1.0")),
            &dir,
        );
        assert!(e.contains("does not apply to a body with `mesh`"), "{e}");
    }
    let e = scene_error(
        &SCENE.replace(
            "group = \"bottom\"",
            "group = \"bottom\"\nregion = [0, 1, 0, 0]",
        ),
        &dir,
    );
    assert!(
        e.contains("`group` cannot be combined with `region`"),
        "{e}"
    );
    // A missing file names the path.
    let e = scene_error(&SCENE.replace("square.msh", "nowhere.msh"), &dir);
    assert!(
        e.contains("nowhere.msh") && e.contains("cannot be read"),
        "{e}"
    );
    // A bad mesh: the scene error carries the file and the problem.
    std::fs::write(
        dir.path().join("bad.msh"),
        square().replace("0.5 0.5 0", "0.5 0.5 1"),
    )
    .unwrap();
    let e = scene_error(&SCENE.replace("square.msh", "bad.msh"), &dir);
    assert!(e.contains("bad.msh") && e.contains("not planar"), "{e}");
    // Text without a directory cannot resolve a relative mesh path.
    let e = Scene::from_toml(SCENE).unwrap_err().to_string();
    assert!(e.contains("from_path"), "{e}");
}

#[test]
fn a_group_on_a_polygon_body_is_refused() {
    let text = r#"
[[body]]
name = "b"
polygon = [[0, 0], [1, 0], [1, 1], [0, 1]]
hmax = 0.5
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "b"
group = "bottom"
"#;
    let e = Scene::from_toml(text).unwrap_err().to_string();
    assert!(
        e.contains("needs a body with `mesh`") && e.contains("use `region`"),
        "{e}"
    );
}

#[test]
fn from_path_resolves_the_mesh_beside_the_scene() {
    let dir = Dir::new("from-path");
    std::fs::write(dir.path().join("scene.toml"), SCENE).unwrap();
    let scene = Scene::from_path(&dir.path().join("scene.toml")).unwrap();
    assert_eq!(
        scene.bodies[0].imported.as_ref().unwrap().mesh.nodes.len(),
        5
    );
}
