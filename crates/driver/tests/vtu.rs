//! solution.vtu read back by an independent reader (the `vtkio` crate, not the writer's code) in
//! both encodings (`--vtu ascii|binary`): every array equals the in-memory mesh and fields —
//! exactly, since both encodings are lossless (ASCII writes floats with `{:e}`, the shortest
//! form that parses back to the same `f64`; binary writes the bytes) — on a two-body P1 scene
//! and a Q1 scene.

#![allow(clippy::unwrap_used)]

mod common;
use common::signorini;

use std::path::{Path, PathBuf};

use signorini::backends::{make_backend, BackendKind};
use signorini::output::{self, BodyField, VtuFormat};
use signorini::run::{self, Outcome};
use signorini_core::mesh::{Cells, MeshLimits};
use signorini_core::qp::SolveOptions;
use signorini_core::scene::Scene;
use vtkio::model::{Attribute, CellType, DataSet, IOBuffer, Piece, VertexNumbers};

const FORMATS: [VtuFormat; 2] = [VtuFormat::Ascii, VtuFormat::Binary];

fn fixture(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(rel)
}

/// `scene` (the default, Experiment 2b, when `None`) solved with clarabel.
fn solved(scene: Option<&Path>) -> (Scene, Outcome) {
    let scene = run::load_scene(scene).expect("valid scene");
    let mut backend = make_backend(BackendKind::Clarabel).expect("clarabel is built in");
    let outcome = run::solve_scene(
        &scene,
        backend.as_mut(),
        &SolveOptions::default(),
        &MeshLimits::default(),
    )
    .expect("the scene solves");
    (scene, outcome)
}

/// One array as vtkio read it.
struct ReadArray {
    name: String,
    data: IOBuffer,
}

/// What vtkio reads from a `.vtu`.
struct Grid {
    points: Vec<f64>,
    connectivity: Vec<u64>,
    offsets: Vec<u64>,
    types: Vec<CellType>,
    point_data: Vec<ReadArray>,
    cell_data: Vec<ReadArray>,
}

fn arrays(attrs: Vec<Attribute>) -> Vec<ReadArray> {
    attrs
        .into_iter()
        .map(|a| match a {
            Attribute::DataArray(d) => ReadArray {
                name: d.name,
                data: d.data,
            },
            Attribute::Field { name, .. } => panic!("unexpected field data {name}"),
        })
        .collect()
}

/// Reads `path` with vtkio.
fn read(path: &Path) -> Grid {
    let vtk = vtkio::Vtk::import(path).unwrap_or_else(|e| panic!("vtkio: {e:?}"));
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("not an UnstructuredGrid");
    };
    assert_eq!(pieces.len(), 1);
    let Piece::Inline(piece) = pieces.into_iter().next().unwrap() else {
        panic!("piece not inline");
    };
    let VertexNumbers::XML {
        connectivity,
        offsets,
    } = piece.cells.cell_verts
    else {
        panic!("legacy cells");
    };
    Grid {
        points: piece.points.into_vec::<f64>().expect("Float64 points"),
        connectivity,
        offsets,
        types: piece.cells.types,
        point_data: arrays(piece.data.point),
        cell_data: arrays(piece.data.cell),
    }
}

fn bodies<'a>(scene: &'a Scene, outcome: &'a Outcome) -> Vec<BodyField<'a>> {
    BodyField::of_bodies(&outcome.model.meshes, &outcome.fields, &scene.bodies)
}

/// Every array of `grid` equals what `bodies` hold — built here from the meshes and fields, not
/// with the writer's code.
fn assert_matches(grid: Grid, bodies: &[BodyField], what: &str) {
    let mut points = Vec::new();
    let mut connectivity = Vec::new();
    let mut offsets = Vec::new();
    let mut types = Vec::new();
    let mut displacement = Vec::new();
    let mut pressure = Vec::new();
    let mut node_body = Vec::new();
    let mut stress = Vec::new();
    let mut von_mises = Vec::new();
    let mut cell_body = Vec::new();
    let mut first = 0u64;
    for (k, b) in bodies.iter().enumerate() {
        for p in &b.mesh.nodes {
            points.extend([p[0], p[1], 0.0]);
        }
        let (per, ty) = match b.mesh.cells {
            Cells::Triangles(_) => (3, CellType::Triangle),
            Cells::Quads(_) => (4, CellType::Quad),
        };
        for c in 0..b.mesh.cells.len() {
            let cell = b.mesh.cells.cell(c);
            assert_eq!(cell.len(), per);
            connectivity.extend(cell.iter().map(|&n| n as u64 + first));
            offsets.push(connectivity.len() as u64);
            types.push(ty);
        }
        first += b.mesh.nodes.len() as u64;
        for u in b.displacement {
            displacement.extend([u[0], u[1], 0.0]);
        }
        pressure.extend_from_slice(b.contact_pressure);
        node_body.extend(std::iter::repeat_n(k as i32, b.mesh.nodes.len()));
        // BodyField: σxx, σyy, σxy, σzz; VTK tensor: XX YY ZZ XY YZ XZ.
        for s in b.stress {
            stress.extend([s[0], s[1], s[3], s[2], 0.0, 0.0]);
        }
        von_mises.extend_from_slice(b.von_mises);
        cell_body.extend(std::iter::repeat_n(k as i32, b.mesh.cells.len()));
    }

    // Exact equality: both encodings are lossless (see the module docs).
    assert_eq!(grid.points, points, "{what}: points");
    assert_eq!(grid.connectivity, connectivity, "{what}: connectivity");
    assert_eq!(grid.offsets, offsets, "{what}: offsets");
    assert_eq!(grid.types, types, "{what}: types");

    let names = |a: &[ReadArray]| a.iter().map(|a| a.name.clone()).collect::<Vec<_>>();
    assert_eq!(
        names(&grid.point_data),
        ["displacement", "contact_pressure", "body_id"],
        "{what}"
    );
    assert_eq!(
        names(&grid.cell_data),
        ["stress", "von_mises", "body_id"],
        "{what}"
    );
    let mut pd = grid.point_data.into_iter().map(|a| a.data);
    let mut cd = grid.cell_data.into_iter().map(|a| a.data);
    // `into_vec::<T>` is `None` unless the array was stored as T (Float64, Int32).
    let f64s = |b: Option<IOBuffer>| b.unwrap().into_vec::<f64>().expect("Float64");
    let i32s = |b: Option<IOBuffer>| b.unwrap().into_vec::<i32>().expect("Int32");
    assert_eq!(f64s(pd.next()), displacement, "{what}: displacement");
    assert_eq!(f64s(pd.next()), pressure, "{what}: contact_pressure");
    assert_eq!(i32s(pd.next()), node_body, "{what}: point body_id");
    assert_eq!(f64s(cd.next()), stress, "{what}: stress");
    assert_eq!(f64s(cd.next()), von_mises, "{what}: von_mises");
    assert_eq!(i32s(cd.next()), cell_body, "{what}: cell body_id");
}

/// Writes the solution of `scene` in both formats through `write_outputs_with` (the path `solve`
/// takes) and checks what vtkio reads against the fields.
fn check_scene(scene: Option<&Path>, want_cells: Cells) {
    let (scene, outcome) = solved(scene);
    let bodies = bodies(&scene, &outcome);
    assert!(bodies.len() >= 2, "a scene of several bodies");
    assert!(bodies
        .iter()
        .all(|b| std::mem::discriminant(&b.mesh.cells) == std::mem::discriminant(&want_cells)));
    // Some contact pressure is nonzero: the comparison covers a nontrivial field.
    assert!(bodies
        .iter()
        .any(|b| b.contact_pressure.iter().any(|&p| p > 0.0)));
    let tmp = tempfile::tempdir().unwrap();
    let mut sizes = Vec::new();
    for format in FORMATS {
        let dir = tmp.path().join(format.as_str());
        run::write_outputs_with(&dir, &scene, &outcome, format).unwrap();
        let path = dir.join("solution.vtu");
        let text = std::fs::read_to_string(&path).unwrap();
        // Well-formed XML in both encodings (base64 appended data is text).
        let doc = roxmltree::Document::parse(&text).unwrap();
        let formats: Vec<&str> = doc
            .descendants()
            .filter(|n| n.has_tag_name("DataArray"))
            .map(|n| n.attribute("format").unwrap())
            .collect();
        assert_eq!(formats.len(), 10);
        let want = match format {
            VtuFormat::Ascii => "ascii",
            VtuFormat::Binary => "appended",
        };
        assert!(formats.iter().all(|f| *f == want), "{formats:?}");
        assert_matches(read(&path), &bodies, &format!("{format}"));
        sizes.push(text.len());
    }
    // Compression at work: float fields of a solution do not compress much, but the text form
    // spends ~23 characters per Float64 and the binary one at most 8 · 4/3 (base64).
    assert!(
        sizes[1] * 2 < sizes[0],
        "binary {} B vs ascii {} B",
        sizes[1],
        sizes[0]
    );
}

#[test]
fn two_body_p1_scene_reads_back_in_both_formats() {
    check_scene(None, Cells::Triangles(Vec::new()));
}

#[test]
fn q1_scene_reads_back_in_both_formats() {
    check_scene(Some(&fixture("seed/exp1.toml")), Cells::Quads(Vec::new()));
}

/// Fields with values that need all 17 digits, subnormals, signed zero and extremes: bit-exact
/// in both encodings; the body names cannot break the XML.
#[test]
fn awkward_values_and_names_read_back_exactly() {
    let (scene, outcome) = solved(None);
    let mut fields = outcome.fields.clone();
    let awkward = [
        0.1 + 0.2,
        -1.0 / 3.0 * 1e-300,
        f64::MIN_POSITIVE / 3.0,
        -0.0,
        f64::MAX,
        -f64::MIN_POSITIVE,
        1e308,
    ];
    for (i, v) in fields[0].von_mises.iter_mut().zip(awkward.iter().cycle()) {
        *i = *v;
    }
    fields[1].displacement[0] = [awkward[2], awkward[3]];
    let names = ["a--b-->\n<VTKFile>-", "\u{1}<&\"'>]]>"];
    let bodies: Vec<BodyField> = outcome
        .model
        .meshes
        .iter()
        .zip(&fields)
        .zip(names)
        .map(|((mesh, f), name)| BodyField {
            name,
            mesh,
            displacement: &f.displacement,
            stress: &f.stress,
            von_mises: &f.von_mises,
            contact_pressure: &f.contact_pressure,
            friction: f.friction.as_ref(),
        })
        .collect();
    assert_eq!(bodies.len(), scene.bodies.len());
    let tmp = tempfile::tempdir().unwrap();
    for format in FORMATS {
        let path = tmp.path().join(format!("{format}.vtu"));
        output::write_vtu_with(&path, &bodies, format).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let doc = roxmltree::Document::parse(&text).unwrap();
        assert_eq!(doc.root_element().tag_name().name(), "VTKFile");
        let grid = read(&path);
        // -0.0 == 0.0 for assert_eq: compare the bits of the value that carries the sign.
        let u = grid.point_data[0].data.clone().into_vec::<f64>().unwrap();
        let first1 = 3 * bodies[0].mesh.nodes.len();
        assert_eq!(u[first1 + 1].to_bits(), (-0.0f64).to_bits(), "{format}");
        assert_matches(grid, &bodies, &format!("{format}"));
    }
}

/// `write_vtu_to` (the signature other commands call) writes the binary form, the same bytes as
/// `write_vtu_to_with(…, Binary)`.
#[test]
fn write_vtu_to_defaults_to_binary() {
    let (scene, outcome) = solved(None);
    let bodies = bodies(&scene, &outcome);
    let mut default = Vec::new();
    output::write_vtu_to(&mut default, &bodies).unwrap();
    let mut binary = Vec::new();
    output::write_vtu_to_with(&mut binary, &bodies, VtuFormat::Binary).unwrap();
    assert_eq!(default, binary);
    let text = String::from_utf8(default).unwrap();
    assert!(text.contains(r#"compressor="vtkZLibDataCompressor""#));
    assert!(text.contains(r#"<AppendedData encoding="base64">_"#));
    assert_eq!(VtuFormat::default(), VtuFormat::Binary);
}

/// `solve` writes binary by default, ASCII with `--vtu ascii`, and refuses other names listing
/// the valid ones.
#[test]
fn solve_vtu_flag() {
    let tmp = tempfile::tempdir().unwrap();
    let (scene, outcome) = solved(None);
    let bodies = bodies(&scene, &outcome);
    for (args, want) in [
        (&["--out", "default"][..], "appended"),
        (&["--out", "bin", "--vtu", "binary"][..], "appended"),
        (&["--out", "asc", "--vtu", "ascii"][..], "ascii"),
    ] {
        let mut all = vec!["solve", "--backend", "clarabel"];
        all.extend_from_slice(args);
        let o = signorini(&all, tmp.path());
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        let path = tmp.path().join(args[1]).join("solution.vtu");
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.contains(&format!(r#"format="{want}""#)),
            "{args:?} should write {want}"
        );
        // The CLI meshes the same default scene: the same geometry, exactly (the fields come
        // from another process's solve and are compared in-process by the tests above).
        let grid = read(&path);
        let points: Vec<f64> = bodies
            .iter()
            .flat_map(|b| b.mesh.nodes.iter().flat_map(|p| [p[0], p[1], 0.0]))
            .collect();
        assert_eq!(grid.points, points, "{args:?}");
        let n_cells: usize = bodies.iter().map(|b| b.mesh.cells.len()).sum();
        assert_eq!(grid.types.len(), n_cells, "{args:?}");
    }
    let o = signorini(&["solve", "--vtu", "binry", "--out", "x"], tmp.path());
    // A usage error is exit code 1 (the program's convention, see src/bin/signorini/main.rs).
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("ascii") && err.contains("binary"),
        "the error lists the formats: {err}"
    );
    assert!(!tmp.path().join("x").exists());
}

/// A frictional scene's VTU adds `tangential_traction`, `slip` (Float64) and `contact_state`
/// (Int32) after `contact_pressure`, read back by vtkio: at each slave node with a row, the
/// traction and state of result.json's contact node at that position (every node of the
/// fixture slides: code 2), and zero / 0 at every other node.
#[test]
fn friction_fields_read_back_beside_result_json() {
    let (scene, outcome) = solved(Some(&fixture("hard/friction-slide.toml")));
    let tmp = tempfile::tempdir().unwrap();
    run::write_outputs_with(tmp.path(), &scene, &outcome, VtuFormat::Binary).unwrap();
    let grid = read(&tmp.path().join("solution.vtu"));
    let names: Vec<&str> = grid.point_data.iter().map(|a| a.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "displacement",
            "contact_pressure",
            "tangential_traction",
            "slip",
            "contact_state",
            "body_id"
        ]
    );
    let take = |name: &str| {
        grid.point_data
            .iter()
            .find(|a| a.name == name)
            .unwrap()
            .data
            .clone()
    };
    let traction = take("tangential_traction").into_vec::<f64>().unwrap();
    let state = take("contact_state").into_vec::<i32>().unwrap();
    let points: Vec<[f64; 2]> = grid.points.chunks(3).map(|p| [p[0], p[1]]).collect();
    let pair = &outcome.report.contacts[0];
    assert!(!pair.nodes.is_empty());
    // The slave body's nodes come after the bodies before it in the file.
    let slave = scene
        .bodies
        .iter()
        .position(|b| b.name == pair.slave)
        .unwrap();
    let first: usize = outcome.model.meshes[..slave]
        .iter()
        .map(|m| m.nodes.len())
        .sum();
    let mut with_row = std::collections::HashSet::new();
    for node in &pair.nodes {
        let k = (first..first + outcome.model.meshes[slave].nodes.len())
            .find(|&k| points[k] == [node.x, node.y])
            .unwrap();
        with_row.insert(k);
        assert_eq!(traction[k], node.tangential_traction.unwrap(), "{node:?}");
        assert_eq!(state[k], 2, "{node:?}");
    }
    for k in (0..points.len()).filter(|k| !with_row.contains(k)) {
        assert_eq!((traction[k], state[k]), (0.0, 0), "node {k}");
    }
    // And pressure.svg draws the friction.
    let svg = std::fs::read_to_string(tmp.path().join("pressure.svg")).unwrap();
    assert!(svg.contains("contact pressure and friction"));
    assert!(svg.contains("tangential traction q"));
    assert!(svg.contains("slip zone"));
}
