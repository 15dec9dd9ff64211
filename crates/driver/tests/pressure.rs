//! `pressure.svg` and the contact fields of `result.json` it is drawn from: `solve` writes the
//! plot exactly when the model has contact rows (and removes a stale one otherwise), in the
//! same output set as the other files; the plot is well-formed SVG whatever the numbers and the
//! text; its markers are result.json's nodes (filled = active, hollow = inactive) at the
//! places their `s` and `pressure` give; and `weight`, `s`, `formulation` hold what the docs
//! say on scenes whose geometry gives them exactly.

#![allow(clippy::unwrap_used, clippy::expect_used)] // tests may unwrap

use std::path::Path;
use std::process::Command;

use signorini::backends::{make_backend, BackendKind};
use signorini::output::pressure::{pair_label, INACTIVE_LABEL};
use signorini::output::render_pressure_svg;
use signorini::run::{self, Outcome};
use signorini_core::mesh::MeshLimits;
use signorini_core::qp::SolveOptions;
use signorini_core::report::RunReport;
use signorini_core::scene::Scene;

/// The palette of every plot (`output::svg::PALETTE`), as SVG writes it: pair k has colour k.
const PALETTE: [&str; 8] = [
    "#0072B2", "#E69F00", "#009E73", "#CC79A7", "#56B4E9", "#D55E00", "#787814", "#3C3C3C",
];

fn fixture(path: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    std::fs::read_to_string(root.join(path)).expect("fixture exists")
}

fn solve(toml: &str) -> (Scene, Outcome) {
    let scene = Scene::from_toml(toml).expect("valid scene");
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

/// A single clamped block under a traction: no contact pair at all.
const NO_CONTACT: &str = r#"
title = "one block, no contact"
[[body]]
name = "block"
polygon = [[0, 0], [1, 0], [1, 1], [0, 1]]
hmax = 0.25
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "block"
region = [0, 1, 0, 0]
[[neumann]]
body = "block"
region = [0, 1, 1, 1]
traction = [0, -1e-3]
"#;

/// Two blocks far apart with a pair: the pair gets no row (no candidate within reach).
const PAIR_WITHOUT_ROWS: &str = r#"
title = "two blocks far apart"
[[body]]
name = "a"
polygon = [[0, 0], [1, 0], [1, 1], [0, 1]]
hmax = 0.25
young = 1.0
poisson = 0.3
[[body]]
name = "b"
polygon = [[0, 3], [1, 3], [1, 4], [0, 4]]
hmax = 0.25
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "a"
region = [0, 1, 0, 0]
[[dirichlet]]
body = "b"
region = [0, 1, 4, 4]
[[contact]]
bodies = ["a", "b"]
"#;

/// One marker of the plot: centre in pixels, and whether it is filled.
#[derive(Debug, Clone, Copy)]
struct Marker {
    x: f64,
    y: f64,
    colour: usize,
    filled: bool,
}

/// Every `<circle>` of the document, in document order, with its palette colour (circles of
/// other colours — the grey legend entry — get `usize::MAX`).
fn markers(svg: &str) -> Vec<Marker> {
    let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
    doc.descendants()
        .filter(|n| n.has_tag_name("circle"))
        .map(|n| {
            let fill = n.attribute("fill").unwrap_or("none");
            let stroke = n.attribute("stroke").unwrap_or("none");
            let filled = fill != "none";
            let colour = if filled { fill } else { stroke };
            Marker {
                x: n.attribute("cx").unwrap().parse().unwrap(),
                y: n.attribute("cy").unwrap().parse().unwrap(),
                colour: PALETTE
                    .iter()
                    .position(|p| p.eq_ignore_ascii_case(colour))
                    .unwrap_or(usize::MAX),
                filled,
            }
        })
        .collect()
}

/// Every text of the document.
fn texts(svg: &str) -> Vec<String> {
    let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .map(|t| t.trim().to_string())
        .collect()
}

/// Checks that the plot's markers are the report's nodes: per pair (in order), its active
/// nodes as filled circles of its colour, then its inactive ones hollow, sorted along the
/// interface; then the legend's circles (one filled per pair, one grey hollow when any node is
/// inactive).  The positions must be one affine map of (s, pressure) for all pairs (both axes
/// are linear; plotters rounds to whole pixels, and the map is fitted from two rounded points,
/// so 1.5 px is the tolerance).
fn check_markers(svg: &str, report: &RunReport) {
    let all = markers(svg);
    let mut expected = Vec::new(); // (colour, filled, s, p)
    let mut legend = Vec::new();
    let mut any_inactive = false;
    for (k, c) in report.contacts.iter().enumerate() {
        if c.nodes.is_empty() {
            continue;
        }
        let mut nodes: Vec<_> = c.nodes.iter().collect();
        nodes.sort_by(|a, b| a.piece.cmp(&b.piece).then(a.s.total_cmp(&b.s)));
        for n in nodes.iter().filter(|n| n.active) {
            expected.push((k, true, n.s, n.pressure));
        }
        for n in nodes.iter().filter(|n| !n.active) {
            expected.push((k, false, n.s, n.pressure));
            any_inactive = true;
        }
        legend.push((k, true));
    }
    if any_inactive {
        legend.push((usize::MAX, false));
    }
    assert_eq!(
        all.len(),
        expected.len() + legend.len(),
        "one circle per node plus the legend's"
    );
    let (data, glyphs) = all.split_at(expected.len());
    for (m, e) in data.iter().zip(&expected) {
        assert_eq!((m.colour, m.filled), (e.0, e.1), "{m:?} for {e:?}");
    }
    for (m, g) in glyphs.iter().zip(&legend) {
        assert_eq!((m.colour, m.filled), *g, "legend glyph {m:?}");
    }
    // The affine maps, from the extreme points (after the plot's own scaling by a power of ten,
    // which an affine map absorbs).
    let fit = |value: &dyn Fn(usize) -> f64, pixel: &dyn Fn(usize) -> f64| {
        let lo = (0..data.len())
            .min_by(|&i, &j| value(i).total_cmp(&value(j)))
            .unwrap();
        let hi = (0..data.len())
            .max_by(|&i, &j| value(i).total_cmp(&value(j)))
            .unwrap();
        let slope = (pixel(hi) - pixel(lo)) / (value(hi) - value(lo));
        assert!(
            (pixel(hi) - pixel(lo)).abs() > 100.0,
            "the data spans the axis"
        );
        for (i, e) in expected.iter().enumerate() {
            let want = pixel(lo) + slope * (value(i) - value(lo));
            assert!(
                (pixel(i) - want).abs() <= 1.5,
                "marker {i} at {} px, (s, p) = ({}, {}) puts it at {want} px",
                pixel(i),
                e.2,
                e.3
            );
        }
    };
    fit(&|i| expected[i].2, &|i| data[i].x);
    fit(&|i| expected[i].3, &|i| data[i].y);
}

#[test]
fn the_markers_of_pressure_svg_are_result_json_s_nodes_on_three_pairs() {
    // Three pairs, all interfaces non-conforming, every node active (the fixture's
    // expectation), and experiment 6a with open nodes (hollow markers).
    for name in ["hard/chain-four.toml", "seed/exp6a.toml", "seed/exp2b.toml"] {
        let (scene, outcome) = solve(&fixture(name));
        let tmp = tempfile::tempdir().unwrap();
        let written = run::write_outputs(tmp.path(), &scene, &outcome).unwrap();
        assert!(written.ends_with(&[tmp.path().join("pressure.svg")]));
        // Read back what result.json holds, not the in-memory report.
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(tmp.path().join("result.json")).unwrap())
                .unwrap();
        let svg = std::fs::read_to_string(tmp.path().join("pressure.svg")).unwrap();
        check_markers(&svg, &outcome.report);
        // The report checked is the file's: same count of active nodes per pair.
        for (c, j) in outcome
            .report
            .contacts
            .iter()
            .zip(json["contacts"].as_array().unwrap())
        {
            let active = j["nodes"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|n| n["active"].as_bool().unwrap())
                .count();
            assert_eq!(active, c.nodes.iter().filter(|n| n.active).count());
            assert_eq!(active, j["active"].as_u64().unwrap() as usize);
        }
        // The legend names every pair with its bodies and formulation.
        let t = texts(&svg);
        for (k, c) in outcome.report.contacts.iter().enumerate() {
            assert!(t.contains(&pair_label(k, c)), "{name}: {t:?}");
        }
        let any_inactive = outcome
            .report
            .contacts
            .iter()
            .any(|c| c.nodes.iter().any(|n| !n.active));
        assert_eq!(
            t.iter().any(|x| x == INACTIVE_LABEL),
            any_inactive,
            "{name}"
        );
    }
}

#[test]
fn experiment_2b_s_is_x_minus_one_and_the_weights_sum_to_the_interface_length() {
    // Slave "upper", interface y = 1 for x in [1, 2], conforming nodes every 0.2: s = x − 1,
    // weights 0.1, 0.2, 0.2, 0.2, 0.2, 0.1 (half of each adjacent interface edge), summing to
    // the interface length 1; pressure = multiplier / weight.  The tolerances are round-off of
    // sums of a few lengths of order 1 (1e-14).
    let (_, outcome) = solve(&fixture("seed/exp2b.toml"));
    let c = &outcome.report.contacts[0];
    assert_eq!(c.slave, "upper");
    let json = serde_json::to_value(c).unwrap();
    assert_eq!(json["formulation"], "node-to-segment");
    assert_eq!(c.nodes.len(), 6);
    let mut total = 0.0;
    for n in &c.nodes {
        assert_eq!(n.piece, 0);
        assert!((n.s - (n.x - 1.0)).abs() < 1e-14, "s {} at x {}", n.s, n.x);
        let interior = n.x > 1.0 + 1e-9 && n.x < 2.0 - 1e-9;
        let want = if interior { 0.2 } else { 0.1 };
        assert!(
            (n.weight - want).abs() < 1e-14,
            "weight {} at x {}",
            n.weight,
            n.x
        );
        assert_eq!(n.pressure, n.multiplier / n.weight);
        total += n.weight;
    }
    assert!((total - 1.0).abs() < 1e-14, "{total}");
    for key in ["weight", "s", "piece"] {
        assert!(json["nodes"][0].get(key).is_some(), "result.json has {key}");
    }
}

#[test]
fn a_mortar_pair_is_named_mortar_in_result_json_and_the_legend() {
    let toml = fixture("seed/exp2b.toml").replace(
        "region = [1, 2, 0.99, 1.01]",
        "region = [1, 2, 0.99, 1.01]\nformulation = \"mortar\"",
    );
    let (scene, outcome) = solve(&toml);
    let json = serde_json::to_value(&outcome.report).unwrap();
    assert_eq!(json["contacts"][0]["formulation"], "mortar");
    let svg = render_pressure_svg(&scene.title, &outcome.report)
        .unwrap()
        .unwrap();
    assert!(
        texts(&svg).contains(&"pair 1: upper (slave) on lower, mortar".to_string()),
        "{:?}",
        texts(&svg)
    );
    check_markers(&svg, &outcome.report);
}

#[test]
fn no_contact_row_no_pressure_svg_and_a_stale_one_is_removed() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    let (scene, outcome) = solve(&fixture("seed/exp2b.toml"));
    run::write_outputs(&dir, &scene, &outcome).unwrap();
    assert!(dir.join("pressure.svg").is_file());
    for toml in [NO_CONTACT, PAIR_WITHOUT_ROWS] {
        let (scene, outcome) = solve(toml);
        assert_eq!(outcome.report.constraints, 0);
        assert!(render_pressure_svg(&scene.title, &outcome.report)
            .unwrap()
            .is_none());
        let written = run::write_outputs(&dir, &scene, &outcome).unwrap();
        assert_eq!(
            written,
            ["result.json", "solution.vtu", "deformed.svg"].map(|f| dir.join(f))
        );
        let mut names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, ["deformed.svg", "result.json", "solution.vtu"]);
        // Put a contact run's set back for the next scene.
        let (scene, outcome) = solve(&fixture("seed/exp2b.toml"));
        run::write_outputs(&dir, &scene, &outcome).unwrap();
        assert!(dir.join("pressure.svg").is_file());
    }
}

#[test]
fn a_failed_write_keeps_the_previous_pressure_svg() {
    // The plot is rendered inside the set: a result whose pressure plot cannot be drawn would
    // fail before the commit.  Simulate the failure the same way files.rs does for the VTU (a
    // field that does not fit its mesh fails before pressure.svg), and check pressure.svg of the
    // earlier run is still there, byte for byte.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    let (scene, outcome) = solve(&fixture("seed/exp2b.toml"));
    run::write_outputs(&dir, &scene, &outcome).unwrap();
    let before = std::fs::read(dir.join("pressure.svg")).unwrap();
    let mut bad = outcome.clone();
    bad.report.contacts[0].nodes[5].pressure *= 2.0; // its plot would differ
    bad.fields[0].displacement.pop();
    assert!(run::write_outputs(&dir, &scene, &bad).is_err());
    assert_eq!(std::fs::read(dir.join("pressure.svg")).unwrap(), before);
}

#[test]
fn any_number_and_any_text_give_a_well_formed_plot() {
    let (mut scene, outcome) = solve(&fixture("seed/exp2b.toml"));
    scene.title = "t\u{1}<&\"'>".repeat(40);
    let cases: [&[f64]; 6] = [
        &[f64::NAN, f64::INFINITY, 1.0],
        &[1e300, -1e300, 0.0],
        &[f64::MAX, 1.0, -f64::MAX],
        &[1e-310, 5e-324, 0.0],
        &[1e300, 1e300 * (1.0 + f64::EPSILON), 1e300],
        &[0.0, 0.0, 0.0],
    ];
    for values in cases {
        let mut report = outcome.report.clone();
        for (i, n) in report.contacts[0].nodes.iter_mut().enumerate() {
            n.pressure = values[i % values.len()];
            n.s = values[(i + 1) % values.len()];
        }
        let svg = render_pressure_svg(&scene.title, &report).unwrap().unwrap();
        let t = texts(&svg);
        assert!(
            t.iter()
                .any(|x| x.starts_with("contact pressure: t\u{FFFD}<&\"'>")),
            "{t:?}"
        );
        let left_out = report.contacts[0]
            .nodes
            .iter()
            .filter(|n| !(n.s.is_finite() && n.pressure.is_finite()))
            .count();
        assert_eq!(
            t.iter()
                .any(|x| x.contains("with a non-finite value left out")),
            left_out > 0,
            "{values:?}: {t:?}"
        );
    }
}

#[test]
fn the_cli_writes_pressure_svg_with_the_other_files() {
    let tmp = tempfile::tempdir().unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_signorini"))
        .args(["solve", "--out", "res"])
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("pressure.svg"), "{stdout}");
    let svg = std::fs::read_to_string(tmp.path().join("res/pressure.svg")).unwrap();
    roxmltree::Document::parse(&svg).unwrap();
}
