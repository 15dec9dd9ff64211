//! Output files as sets: `solve`'s and `compare`'s files are replaced together or not at all,
//! a second run into a directory in use is refused, nothing temporary is left behind, and any
//! text in a scene makes well-formed SVG and VTU.

mod common;
use common::signorini;

use std::path::{Path, PathBuf};

use signorini::backends::{make_backend, BackendKind};
use signorini::compare;
use signorini::outdir::DirLock;
use signorini::output::OutputError;
use signorini::run::{self, Outcome};
use signorini_core::mesh::MeshLimits;
use signorini_core::qp::SolveOptions;
use signorini_core::scene::Scene;

/// The default scene (Experiment 2b), solved with clarabel.
fn solved() -> (Scene, Outcome) {
    let scene = run::load_scene(None).expect("the default scene is valid");
    let mut backend = make_backend(BackendKind::Clarabel).expect("clarabel is built in");
    let outcome = run::solve_scene(
        &scene,
        backend.as_mut(),
        &SolveOptions::default(),
        &MeshLimits::default(),
    )
    .expect("the default scene solves");
    (scene, outcome)
}

/// Every entry of `dir` (hidden ones included) with its bytes, sorted by name.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .expect("readable directory")
        .map(|e| {
            let e = e.expect("readable entry");
            let bytes = if e.file_type().expect("file type").is_dir() {
                b"<directory>".to_vec()
            } else {
                std::fs::read(e.path()).expect("readable file")
            };
            (e.file_name().to_string_lossy().into_owned(), bytes)
        })
        .collect();
    v.sort();
    v
}

fn names(dir: &Path) -> Vec<String> {
    snapshot(dir).into_iter().map(|e| e.0).collect()
}

fn file_names(paths: &[PathBuf]) -> Vec<String> {
    paths
        .iter()
        .map(|p| {
            p.file_name()
                .expect("a file path")
                .to_string_lossy()
                .into_owned()
        })
        .collect()
}

#[test]
fn a_failed_write_leaves_the_previous_solve_byte_identical() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    let (scene, outcome) = solved();
    let written = run::write_outputs(&dir, &scene, &outcome).unwrap();
    assert_eq!(
        file_names(&written),
        [
            "result.json",
            "solution.vtu",
            "deformed.svg",
            "pressure.svg"
        ]
    );
    let before = snapshot(&dir);
    assert_eq!(
        names(&dir),
        [
            "deformed.svg",
            "pressure.svg",
            "result.json",
            "solution.vtu"
        ]
    );

    // A second result whose fields do not fit its mesh: result.json is staged first, then the
    // VTU writer fails.  Before output sets, result.json was already replaced at that point.
    let mut bad = outcome.clone();
    bad.report.scene.push_str(" (second run)"); // so its result.json differs
    bad.fields[0].displacement.pop();
    let err = run::write_outputs(&dir, &scene, &bad).unwrap_err();
    assert!(matches!(err, OutputError::Mismatch(_)), "{err:?}");
    assert_eq!(snapshot(&dir), before, "the previous set must be untouched");

    // The same result written again replaces the set, still without stray files.
    run::write_outputs(&dir, &scene, &outcome).unwrap();
    assert_eq!(
        names(&dir),
        [
            "deformed.svg",
            "pressure.svg",
            "result.json",
            "solution.vtu"
        ]
    );
}

#[test]
fn a_directory_in_use_is_refused_by_every_writer() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("busy");
    let (scene, outcome) = solved();
    run::write_outputs(&dir, &scene, &outcome).unwrap();
    let before = snapshot(&dir);

    let held = DirLock::acquire(&dir).unwrap();
    let err = run::write_outputs(&dir, &scene, &outcome).unwrap_err();
    assert!(matches!(err, OutputError::Locked { .. }), "{err:?}");
    assert!(
        err.to_string().contains(&dir.display().to_string()),
        "{err}"
    );

    let report = compare::compare(
        &scene,
        &[BackendKind::Clarabel],
        &SolveOptions::default(),
        &MeshLimits::default(),
        |_| {},
    )
    .unwrap();
    let err = compare::write(&dir, &report).unwrap_err();
    assert!(matches!(err, OutputError::Locked { .. }), "{err:?}");

    // Another process: the lock is an OS-level advisory lock, not a flag of this process.
    let o = signorini(&["solve", "--out", "busy"], tmp.path());
    assert!(!o.status.success());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("busy") && stderr.contains("in use"),
        "{stderr}"
    );
    let o = signorini(
        &[
            "sweep",
            "--hmax",
            "0.3",
            "--backends",
            "clarabel",
            "--out",
            "busy",
        ],
        tmp.path(),
    );
    assert!(!o.status.success());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("in use"), "{stderr}");
    assert_eq!(snapshot(&dir), before);

    drop(held);
    let written = compare::write(&dir, &report).unwrap();
    assert_eq!(file_names(&written), ["compare.json", "compare.csv"]);
    assert_eq!(
        names(&dir),
        [
            "compare.csv",
            "compare.json",
            "deformed.svg",
            "pressure.svg",
            "result.json",
            "solution.vtu"
        ]
    );
}

#[test]
fn any_title_and_body_name_give_well_formed_files() {
    let tmp = tempfile::tempdir().unwrap();
    let (mut scene, outcome) = solved();
    // Set after validation, so this holds whatever the scene parser accepts.
    scene.title = "t\u{1}<&\"'>".into();
    scene.bodies[0].name = "b\u{1}<&\"'>".into();
    run::write_outputs(tmp.path(), &scene, &outcome).unwrap();

    let svg = std::fs::read_to_string(tmp.path().join("deformed.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let texts: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .map(str::trim)
        .collect();
    assert!(texts.contains(&"t\u{FFFD}<&\"'>"), "{texts:?}");
    assert!(texts.contains(&"b\u{FFFD}<&\"'>"), "{texts:?}");

    let vtu = std::fs::read_to_string(tmp.path().join("solution.vtu")).unwrap();
    let doc = roxmltree::Document::parse(&vtu).unwrap();
    let comment = doc
        .root()
        .children()
        .find(|n| n.is_comment())
        .and_then(|n| n.text())
        .unwrap();
    assert!(comment.contains("0 = b\u{FFFD}<&\"'>"), "{comment}");
}
