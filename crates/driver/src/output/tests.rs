#![allow(clippy::unwrap_used)]

use std::io;
use std::path::Path;

use signorini_core::mesh::{Cells, Mesh};

use super::*;

/// Two triangles on the unit square [x0, x0+1] × [y0, y0+1].
fn tri_square(x0: f64, y0: f64) -> Mesh {
    Mesh {
        nodes: vec![
            [x0, y0],
            [x0 + 1.0, y0],
            [x0 + 1.0, y0 + 1.0],
            [x0, y0 + 1.0],
        ],
        cells: Cells::Triangles(vec![[0, 1, 2], [0, 2, 3]]),
        boundary: vec![[0, 1], [1, 2], [2, 3], [3, 0]],
    }
}

/// A 2 × 1 grid of quads on [x0, x0+2] × [y0, y0+1].
fn quad_strip(x0: f64, y0: f64) -> Mesh {
    Mesh {
        nodes: vec![
            [x0, y0],
            [x0 + 1.0, y0],
            [x0 + 2.0, y0],
            [x0, y0 + 1.0],
            [x0 + 1.0, y0 + 1.0],
            [x0 + 2.0, y0 + 1.0],
        ],
        cells: Cells::Quads(vec![[0, 1, 4, 3], [1, 2, 5, 4]]),
        boundary: vec![[0, 1], [1, 2], [2, 5], [5, 4], [4, 3], [3, 0]],
    }
}

/// Owned fields for a mesh.
struct Fields {
    u: Vec<[f64; 2]>,
    s: Vec<[f64; 4]>,
    vm: Vec<f64>,
    p: Vec<f64>,
}

fn fields(mesh: &Mesh, scale: f64) -> Fields {
    let n = mesh.nodes.len();
    let c = mesh.cells.len();
    Fields {
        u: (0..n)
            .map(|i| [scale * (i as f64 + 0.1), -scale * (i as f64) / 3.0])
            .collect(),
        s: (0..c)
            .map(|i| [i as f64, 1.0 / 3.0, -2.5e-7, 0.1 * i as f64])
            .collect(),
        vm: (0..c).map(|i| 1.0 + i as f64 / 7.0).collect(),
        p: (0..n).map(|i| if i < 2 { 1e-5 } else { 0.0 }).collect(),
    }
}

fn body<'a>(name: &'a str, mesh: &'a Mesh, f: &'a Fields) -> BodyField<'a> {
    BodyField {
        name,
        mesh,
        displacement: &f.u,
        stress: &f.s,
        von_mises: &f.vm,
        contact_pressure: &f.p,
        friction: None,
    }
}

fn dir_entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn parse_numbers<T: std::str::FromStr>(node: roxmltree::Node) -> Vec<T>
where
    T::Err: std::fmt::Debug,
{
    node.text()
        .unwrap_or("")
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect()
}

fn array<'a, 'i>(
    doc: &'a roxmltree::Document<'i>,
    parent: &str,
    name: &str,
) -> roxmltree::Node<'a, 'i> {
    doc.descendants()
        .find(|n| n.has_tag_name(parent))
        .unwrap()
        .children()
        .find(|n| n.has_tag_name("DataArray") && n.attribute("Name") == Some(name))
        .unwrap_or_else(|| panic!("no {parent}/{name}"))
}

#[test]
fn vtu_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("solution.vtu");
    let (m0, m1) = (tri_square(0.0, 1.0), quad_strip(1.0, 0.0));
    let mut f0 = fields(&m0, 1.0e-3);
    // A value that needs all 17 significant digits.
    f0.u[2] = [0.1 + 0.2, -1.0 / 3.0 * 1e-300];
    let f1 = fields(&m1, 2.0e-3);
    let bodies = [body("upper", &m0, &f0), body("lower", &m1, &f1)];
    // The text layout; tests/vtu.rs reads both encodings back with an independent reader.
    write_vtu_with(&path, &bodies, VtuFormat::Ascii).unwrap();
    assert_eq!(dir_entries(dir.path()), ["solution.vtu"]);

    let text = std::fs::read_to_string(&path).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let piece = doc.descendants().find(|n| n.has_tag_name("Piece")).unwrap();
    assert_eq!(piece.attribute("NumberOfPoints"), Some("10"));
    assert_eq!(piece.attribute("NumberOfCells"), Some("4"));

    let pts: Vec<f64> = parse_numbers(array(&doc, "Points", "Points"));
    assert_eq!(pts.len(), 30);
    assert_eq!(&pts[12..15], &[1.0, 0.0, 0.0]); // first node of body 1
    let conn: Vec<usize> = parse_numbers(array(&doc, "Cells", "connectivity"));
    assert_eq!(conn, [0, 1, 2, 0, 2, 3, 4, 5, 8, 7, 5, 6, 9, 8]);
    let offsets: Vec<usize> = parse_numbers(array(&doc, "Cells", "offsets"));
    assert_eq!(offsets, [3, 6, 10, 14]);
    let types: Vec<u8> = parse_numbers(array(&doc, "Cells", "types"));
    assert_eq!(types, [5, 5, 9, 9]);

    let u: Vec<f64> = parse_numbers(array(&doc, "PointData", "displacement"));
    assert_eq!(u.len(), 30);
    assert_eq!(u[6], 0.1 + 0.2); // exact round trip
    assert_eq!(u[7], -1.0 / 3.0 * 1e-300);
    assert_eq!(u[8], 0.0);
    assert_eq!([u[12], u[13]], f1.u[0]);
    let p: Vec<f64> = parse_numbers(array(&doc, "PointData", "contact_pressure"));
    assert_eq!(p.len(), 10);
    assert_eq!(p[0], 1e-5);
    let pid: Vec<i32> = parse_numbers(array(&doc, "PointData", "body_id"));
    assert_eq!(pid, [0, 0, 0, 0, 1, 1, 1, 1, 1, 1]);

    let s: Vec<f64> = parse_numbers(array(&doc, "CellData", "stress"));
    assert_eq!(s.len(), 24);
    // Cell 1 of body 0: σxx = 1, σyy = 1/3, σxy = -2.5e-7, σzz = 0.1 → XX YY ZZ XY YZ XZ.
    assert_eq!(&s[6..12], &[1.0, 1.0 / 3.0, 0.1, -2.5e-7, 0.0, 0.0]);
    let vm: Vec<f64> = parse_numbers(array(&doc, "CellData", "von_mises"));
    assert_eq!(vm, [1.0, 1.0 + 1.0 / 7.0, 1.0, 1.0 + 1.0 / 7.0]);
    let cid: Vec<i32> = parse_numbers(array(&doc, "CellData", "body_id"));
    assert_eq!(cid, [0, 0, 1, 1]);
    assert_eq!(
        array(&doc, "CellData", "body_id").attribute("type"),
        Some("Int32")
    );
}

#[test]
fn mismatch_is_an_error_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let m = tri_square(0.0, 0.0);
    let mut f = fields(&m, 1.0);
    f.vm.pop();
    let path = dir.path().join("bad.vtu");
    let err = write_vtu(&path, &[body("upper", &m, &f)]).unwrap_err();
    let msg = err.to_string();
    assert!(matches!(err, OutputError::Mismatch(_)), "{msg}");
    assert!(msg.contains("upper") && msg.contains("von_mises"), "{msg}");
    let svg = dir.path().join("bad.svg");
    assert!(matches!(
        write_deformed_svg(&svg, "t", &[body("upper", &m, &f)]),
        Err(OutputError::Mismatch(_))
    ));
    assert!(dir_entries(dir.path()).is_empty());

    let mut f = fields(&m, 1.0);
    f.u.push([0.0, 0.0]);
    let msg = write_vtu(&path, &[body("lower", &m, &f)])
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("lower") && msg.contains("displacement"),
        "{msg}"
    );

    let bad_mesh = Mesh {
        cells: Cells::Triangles(vec![[0, 1, 7]]),
        ..tri_square(0.0, 0.0)
    };
    let mut f = fields(&m, 1.0);
    f.s.pop();
    f.vm.pop();
    let msg = write_vtu(&path, &[body("b", &bad_mesh, &f)])
        .unwrap_err()
        .to_string();
    assert!(msg.contains("node 7"), "{msg}");
    assert!(dir_entries(dir.path()).is_empty());
}

#[test]
fn atomic_write_into_missing_directory_fails_with_path() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("no-such-dir").join("out.vtu");
    let err = write_atomically(&path, |w| w.write_all(b"x")).unwrap_err();
    assert!(matches!(err, OutputError::Io { .. }));
    assert!(
        err.to_string().contains(&path.display().to_string()),
        "{err}"
    );
    assert!(dir_entries(dir.path()).is_empty());
}

#[test]
fn failing_writer_leaves_nothing_and_keeps_old_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.txt");
    let err = write_atomically(&path, |w| {
        w.write_all(b"partial")?;
        Err(io::Error::other("boom"))
    })
    .unwrap_err();
    // The cause travels in the error's source chain (the CLI prints the whole chain).
    let cause = std::error::Error::source(&err)
        .map(|s| s.to_string())
        .unwrap_or_default();
    assert!(cause.contains("boom"), "{err}: {cause}");
    assert!(dir_entries(dir.path()).is_empty());

    write_atomically(&path, |w| w.write_all(b"old")).unwrap();
    assert!(write_atomically(&path, |_| Err(io::Error::other("boom"))).is_err());
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
    assert_eq!(dir_entries(dir.path()), ["out.txt"]);
}

#[test]
fn magnification_is_readable() {
    let m = tri_square(0.0, 0.0); // size 1
    let mut f = fields(&m, 0.0);
    assert_eq!(magnification(&[body("a", &m, &f)]), 1.0);
    for (umax, want) in [
        (1e-3, 100.0),
        (1.3e-3, 100.0),
        (2e-3, 50.0),
        (4e-4, 200.0),
        (0.02, 5.0),
        (0.05, 2.0),
        (0.1, 1.0),
        (3.0, 1.0),
        (1e-9, 1e8),
    ] {
        f.u = vec![[0.0, 0.0], [0.0, -umax], [umax / 2.0, 0.0], [0.0, 0.0]];
        assert_eq!(magnification(&[body("a", &m, &f)]), want, "umax = {umax}");
    }
    f.u[0] = [f64::NAN, 0.0];
    assert_eq!(magnification(&[body("a", &m, &f)]), 1.0);
    assert_eq!(magnification(&[]), 1.0);
}

#[test]
fn svg_has_labels_and_each_edge_once() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("deformed.svg");
    let (m0, m1) = (tri_square(0.0, 1.0), quad_strip(1.0, 0.0));
    let mut f0 = fields(&m0, 0.0);
    f0.u = vec![[0.0, -1e-3], [0.0, -1e-3], [0.0, 0.0], [0.0, 0.0]];
    let f1 = fields(&m1, 0.0);
    let bodies = [body("upper", &m0, &f0), body("lower & base", &m1, &f1)];
    assert_eq!(magnification(&bodies), 200.0);
    write_deformed_svg(&path, "Experiment <2b>", &bodies).unwrap();
    assert_eq!(dir_entries(dir.path()), ["deformed.svg"]);
    let svg = std::fs::read_to_string(&path).unwrap();
    assert!(svg.contains("displacement × 200"), "{svg}");
    assert!(svg.contains("upper"));
    assert!(svg.contains("lower &amp; base"));
    assert!(svg.contains("Experiment &lt;2b&gt;"));
    assert!(svg.contains("contact (active)"));
    roxmltree::Document::parse(&svg).unwrap();
}

#[test]
fn edges_are_unique_and_chained_once() {
    let m = quad_strip(0.0, 0.0);
    let edges = svg::unique_edges(&m);
    assert_eq!(edges.len(), 7);
    let chains = svg::chain_edges(&edges, m.nodes.len());
    let mut seen: Vec<[usize; 2]> = chains
        .iter()
        .flat_map(|c| c.windows(2).map(|w| [w[0].min(w[1]), w[0].max(w[1])]))
        .collect();
    seen.sort_unstable();
    assert_eq!(seen, edges);
}

/// A name with a control character (forbidden in XML 1.0) and every character XML escapes.
const NASTY: &str = "\u{1}<&\"'>";
/// What [`NASTY`] reads back as: the control character replaced by U+FFFD, the rest as given.
const NASTY_READ: &str = "\u{FFFD}<&\"'>";

#[test]
fn xml_text_is_escaped_and_forbidden_characters_replaced() {
    assert_eq!(xml_escape(NASTY), "\u{FFFD}&lt;&amp;&quot;&apos;&gt;");
    assert_eq!(xml_sanitize(NASTY), NASTY_READ);
    // Tab, newline and carriage return are allowed; U+FFFE/U+FFFF and C0 controls are not.
    assert_eq!(
        xml_sanitize("a\tb\nc\rd\u{0}\u{1f}\u{7f}\u{FFFE}\u{FFFF}é"),
        "a\tb\nc\rd\u{FFFD}\u{FFFD}\u{7f}\u{FFFD}\u{FFFD}é"
    );
    // Every escaped string is well-formed character data and an attribute value that reads
    // back as the sanitised text.
    for s in [NASTY, "plain", "", "]]>", "a\u{b}b"] {
        let doc = format!("<r a=\"{0}\">{0}</r>", xml_escape(s));
        let parsed = roxmltree::Document::parse(&doc).unwrap();
        let root = parsed.root_element();
        assert_eq!(root.text().unwrap_or(""), xml_sanitize(s));
        assert_eq!(root.attribute("a").unwrap(), xml_sanitize(s));
    }
}

#[test]
fn svg_and_vtu_with_control_characters_in_names_parse_and_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let (m0, m1) = (tri_square(0.0, 1.0), quad_strip(1.0, 0.0));
    let f0 = fields(&m0, 1e-3);
    let f1 = fields(&m1, 1e-3);
    let name1 = format!("lower {NASTY}");
    let bodies = [body(NASTY, &m0, &f0), body(&name1, &m1, &f1)];
    let title = format!("title {NASTY}");

    let svg_path = dir.path().join("deformed.svg");
    write_deformed_svg(&svg_path, &title, &bodies).unwrap();
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap_or_else(|e| panic!("{e}\n{svg}"));
    // plotters wraps each text in newlines.
    let texts: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .map(str::trim)
        .collect();
    for want in [
        format!("title {NASTY_READ}"),
        NASTY_READ.to_string(),
        format!("lower {NASTY_READ}"),
    ] {
        assert!(texts.contains(&want.as_str()), "{want:?} not in {texts:?}");
    }

    for format in [VtuFormat::Ascii, VtuFormat::Binary] {
        let vtu_path = dir.path().join("solution.vtu");
        write_vtu_with(&vtu_path, &bodies, format).unwrap();
        let vtu = std::fs::read_to_string(&vtu_path).unwrap();
        let doc = roxmltree::Document::parse(&vtu).unwrap_or_else(|e| panic!("{e}\n{vtu}"));
        let comment = doc
            .root()
            .children()
            .find(|n| n.is_comment())
            .and_then(|n| n.text())
            .unwrap();
        let names: Vec<&str> = comment
            .lines()
            .skip(1)
            .filter_map(|l| l.split_once(" = ").map(|(_, name)| name))
            .collect();
        assert_eq!(
            names,
            [NASTY_READ.to_string(), format!("lower {NASTY_READ}")],
            "{format}"
        );
    }
}

#[test]
fn vtu_comment_stays_a_comment() {
    let dir = tempfile::tempdir().unwrap();
    let m = tri_square(0.0, 0.0);
    let f = fields(&m, 1e-3);
    let path = dir.path().join("solution.vtu");
    for format in [VtuFormat::Ascii, VtuFormat::Binary] {
        write_vtu_with(&path, &[body("a--b-->\n<VTKFile>-", &m, &f)], format).unwrap();
        let vtu = std::fs::read_to_string(&path).unwrap();
        let doc = roxmltree::Document::parse(&vtu).unwrap();
        assert_eq!(doc.root_element().tag_name().name(), "VTKFile");
        assert_eq!(
            doc.descendants()
                .filter(|n| n.has_tag_name("VTKFile"))
                .count(),
            1,
            "{format}"
        );
    }
}
