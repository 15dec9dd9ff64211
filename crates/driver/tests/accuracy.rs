//! Discretisation accuracy against analytic answers (issue 10): the Hertz cylinder on a block
//! with mortar contact and a graded mesh against Johnson's formulas (within 1 %, and converging
//! as h falls), the patch test's uniform pressure through `signorini study`, and the `study`
//! command's files and refusals.

#![allow(clippy::unwrap_used)]

mod common;
use common::signorini;

use std::path::{Path, PathBuf};

use signorini::auto::AutoBackend;
use signorini::run;
use signorini::study::{derive_scene, read_points, Combination, MeshKind};
use signorini_core::accuracy::{accuracy, Accuracy};
use signorini_core::mesh::{ElementKind, MeshLimits};
use signorini_core::qp::{QpStatus, SolveOptions};
use signorini_core::scene::{Formulation, Scene};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fixtures/accuracy/{name}"))
}

/// Johnson's Hertz line contact for two equal cylinders' worth of material (the block is a
/// cylinder of infinite radius): E* = E / (2(1 − ν²)), a = √(4PR/(πE*)), p₀ = 2P/(πa), computed
/// here from the load the run actually applied (not from the fixture's [reference]).
fn johnson(load: f64) -> (f64, f64) {
    let (e, nu, r) = (1.0_f64, 0.3_f64, 1.0_f64);
    let e_star = e / (2.0 * (1.0 - nu * nu));
    let a = (4.0 * load * r / (std::f64::consts::PI * e_star)).sqrt();
    (a, 2.0 * load / (std::f64::consts::PI * a))
}

const MORTAR_GRADED_P1: Combination = Combination {
    formulation: Formulation::Mortar,
    mesh: MeshKind::Graded,
    element: ElementKind::P1,
};

/// The graded Hertz fixture at body size `h` for mortar: `derive_scene` scales both bodies'
/// hmax and their refine boxes' (h/8), and the cap's arc is re-sampled at the refine box's
/// size.  The fixture's arc vertices are every 0.002, its refine boxes' hmax: a polygon kept
/// at 0.002 would be 4× finer than the elements at h = 0.064, and a boundary finer than its
/// elements makes the nodal contact forces alternate node to node (BENCHMARKS.md, "Hertz:
/// mortar on a curved slave": ±2.5 %), which the max nodal pressure reads.
fn hertz_graded_at(h: f64) -> Scene {
    let scene = Scene::from_path(&fixture("hertz-graded.toml")).unwrap();
    let mut s = derive_scene(&scene, &MORTAR_GRADED_P1, h);
    let cap = s.bodies.iter_mut().find(|b| b.name == "cap").unwrap();
    let zone = cap.refine[0].hmax;
    assert!((zone / h - 0.125).abs() < 1e-12, "refine box at h/8");
    // The fixture was written by the same rule (vertices every 0.002 at its own h = 0.016).
    let written = common::hertz_cap_polygon(0.002);
    assert_eq!(
        scene.bodies[0].polygon.len(),
        written.len(),
        "the fixture's arc"
    );
    for (p, q) in scene.bodies[0].polygon.iter().zip(&written) {
        assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
    }
    cap.polygon = common::hertz_cap_polygon(zone);
    s
}

/// Solves the graded Hertz fixture with mortar at body size `h` (refine boxes and the arc's
/// vertex spacing scaled alike, see [`hertz_graded_at`]) and returns its errors against
/// Johnson's formulas, with the DOFs.
fn hertz_mortar_graded(h: f64) -> (f64, f64, f64, usize) {
    let s = hertz_graded_at(h);
    let mut backend = AutoBackend::default();
    let o = run::solve_scene(
        &s,
        &mut backend,
        &SolveOptions::default(),
        &MeshLimits::default(),
    )
    .unwrap();
    assert_eq!(
        o.solution.status,
        QpStatus::Solved,
        "{:?}",
        o.report.residuals
    );
    let cap = o.report.bodies.iter().find(|b| b.name == "cap").unwrap();
    let load = -cap.applied[1];
    let (a, p0) = johnson(load);
    // The fixture's [reference] holds the same figures (it was generated from them).
    let reference = s.reference.clone().unwrap();
    assert!((reference.half_width.unwrap() / a - 1.0).abs() < 1e-12);
    assert!((reference.peak_pressure.unwrap() / p0 - 1.0).abs() < 1e-12);
    // The cap is held by contact alone in y, so the vertical components of the contact forces
    // add up to the load.  Mortar's multipliers act along the master's normals (the block's:
    // vertical, so Σλ = P to the solver's tolerance; were the master curved, tilted by θ ≤ a/R
    // in the contact zone, Σλ would exceed P by at most 1/cos θ − 1 ≈ (a/R)²/2).
    let force = o.report.contacts[0].normal_force;
    let tilt = 0.5 * (a / 1.0_f64).powi(2);
    assert!(
        force >= load * (1.0 - 1e-6) && force <= load * (1.0 + tilt),
        "Σλ {force:e}, P {load:e}"
    );
    let Accuracy {
        half_width,
        peak_pressure,
        peak_nodal_pressure,
        ..
    } = accuracy(&reference, &o.report).unwrap();
    let ea = half_width.unwrap().computed / a - 1.0;
    let ep = peak_pressure.unwrap().computed / p0 - 1.0;
    let en = peak_nodal_pressure.unwrap().computed / p0 - 1.0;
    eprintln!(
        "h {h}: {} DOFs, a {ea:+.4e}, p0 (fit) {ep:+.4e}, p0 (max nodal) {en:+.4e}",
        o.report.dofs
    );
    (ea, ep, en, o.report.dofs)
}

/// The fixture as written (bodies hmax 0.016, contact zone 0.002: a/h = 25).  The issue asks
/// for 1 %.  Budget, each part well below it: the second-moment estimator's bias
/// (h/a)²/3 = 0.05 % (see `signorini_core::accuracy`); the finite bodies (16a deep, 12a high)
/// against Hertz's half-spaces: a 3.2 × 1.6 block with a half-disc cap moves a by 0.001 %
/// (BENCHMARKS.md, "Hertz convergence, four meshes"); the terms of order (a/R)² = 0.25 % that
/// Hertz's small-slope theory and the linearised contact conditions neglect; and the
/// discretisation error at a/h = 25.
#[test]
fn hertz_with_mortar_on_a_graded_mesh_is_within_one_percent_of_johnson() {
    let (ea, ep, en, _) = hertz_mortar_graded(0.016);
    assert!(ea.abs() <= 0.01, "half-width off by {:.3} %", 100.0 * ea);
    assert!(ep.abs() <= 0.01, "peak pressure off by {:.3} %", 100.0 * ep);
    assert!(
        en.abs() <= 0.01,
        "max nodal pressure off by {:.3} %",
        100.0 * en
    );
}

/// Four meshes, each half the size of the previous (contact zone a/6.25, a/12.5, a/25, a/50;
/// 6 k to 225 k DOFs), the arc re-sampled at the zone's size at each (see [`hertz_graded_at`]).
///
/// The half-width comes from ∫ s² λ, a smooth functional of the multiplier, so its error is
/// bounded by the multiplier's H^{-1/2} error, which is bounded by the energy error (inf–sup);
/// for Signorini problems with linear elements that is proven O(h^{3/4}) without assumptions on
/// the contact set (Hild & Laborde 2002), O(h) with them (Hüeber & Wohlmuth 2005): the Hertz
/// contact set is one interval whose ends the pressure leaves as a square root, the case those
/// assumptions cover.  So the observed rate of the half-width error over the four meshes must
/// be ≥ 1, and each refinement must lower it.  The peak pressure, pointwise, is only required
/// to fall over the 8× refinement, by the fit and at the nodes.  The error left at a/50,
/// −0.017 %, is about the h-independent part measured on other scenes (BENCHMARKS.md, "Hertz
/// convergence, four meshes (issue 21)"): bodies twice as large move a by 0.001 %, R = 4 at
/// the same a/h by ~0.03 % (the (a/R)² terms); the rate is read on the raw errors.
#[test]
fn hertz_errors_fall_as_the_graded_mesh_is_refined() {
    let hs = [0.064, 0.032, 0.016, 0.008];
    let runs: Vec<(f64, f64, f64, usize)> = hs.iter().map(|&h| hertz_mortar_graded(h)).collect();
    for w in runs.windows(2) {
        assert!(w[1].3 > w[0].3, "DOFs grow as h falls");
        assert!(
            w[1].0.abs() < w[0].0.abs(),
            "half-width error must fall: {:e} then {:e}",
            w[0].0,
            w[1].0
        );
    }
    let last = runs.len() - 1;
    for (what, first, last) in [
        ("peak pressure (fit)", runs[0].1.abs(), runs[last].1.abs()),
        (
            "peak pressure (max nodal)",
            runs[0].2.abs(),
            runs[last].2.abs(),
        ),
    ] {
        assert!(last < first, "{what} error must fall: {first:e} → {last:e}");
    }
    let pts: Vec<(f64, f64)> = hs.iter().zip(&runs).map(|(h, r)| (*h, r.0.abs())).collect();
    let rate = signorini::plots::fit_slope(&pts).unwrap();
    assert!(
        rate >= 1.0,
        "observed rate of the half-width error {rate:.2} < 1 (Hüeber & Wohlmuth's O(h))"
    );
}

/// The patch test through `signorini study` with mortar: the exact pressure is uniform
/// (p = 0.01, see the fixture), and mortar reproduces it at every slave node to round-off on
/// non-matching meshes (issue 10 asks 1e-8).
#[test]
fn the_patch_test_with_mortar_is_exact_at_every_size_and_element() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("patch.toml");
    let args = [
        "study",
        scene.to_str().unwrap(),
        "--hmax",
        "0.2,0.1,0.05",
        "--formulations",
        "mortar",
        "--meshes",
        "uniform",
        "--out",
        "s",
    ];
    let o = signorini(&args, dir.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let points = read_points(&dir.path().join("s/study.csv")).unwrap();
    assert_eq!(points.len(), 2 * 3, "p1 and q1 at three sizes");
    for p in &points {
        let dev = p.pressure_deviation.unwrap();
        assert!(
            dev <= 1e-8,
            "{} at hmax {}: {dev:e}",
            p.combination(),
            p.hmax
        );
    }
}

#[test]
fn study_writes_one_row_per_applicable_point_and_a_plot() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("patch.toml");
    let args = [
        "study",
        scene.to_str().unwrap(),
        "--hmax",
        "0.2,0.1",
        "--formulations",
        "node-to-segment,mortar",
        "--meshes",
        "uniform,graded",
        "--elements",
        "p1",
        "--backend",
        "clarabel",
        "--out",
        "s",
    ];
    let o = signorini(&args, dir.path());
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The patch scene has no refine box: graded does not apply, and the output says so.
    assert!(
        stdout.contains("skipped node-to-segment, graded, p1: does not apply")
            && stdout.contains("skipped mortar, graded, p1: does not apply"),
        "{stdout}"
    );
    let csv = dir.path().join("s/study.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(
        text.lines().next().unwrap(),
        signorini::study::COLUMNS.join(",")
    );
    let points = read_points(&csv).unwrap();
    let got: Vec<(String, f64)> = points.iter().map(|p| (p.combination(), p.hmax)).collect();
    let want: Vec<(String, f64)> = [
        ("node-to-segment, uniform, p1", 0.2),
        ("node-to-segment, uniform, p1", 0.1),
        ("mortar, uniform, p1", 0.2),
        ("mortar, uniform, p1", 0.1),
    ]
    .iter()
    .map(|(c, h)| (c.to_string(), *h))
    .collect();
    assert_eq!(got, want);
    for p in &points {
        assert_eq!(p.status, "solved");
        assert_eq!(p.backend, "clarabel");
        // The lower block's hmax is the coarsest: it takes --hmax, the upper keeps 0.07 : 0.1.
        assert!((p.hmin / p.hmax - 0.7).abs() < 1e-12, "{p:?}");
        assert!((p.total_s - (p.mesh_s + p.assemble_s + p.solve_s)).abs() <= 1e-12 * p.total_s);
        assert!(p.pressure_deviation.is_some() && p.error_half_width.is_none());
    }
    // Node-to-segment on the non-matching 0.07 : 0.1 interface misses the uniform pressure by
    // ~12.6 % (issue 10); the study must see it, so the column measures something.
    let nts = points.iter().find(|p| p.hmax == 0.1).unwrap();
    assert!(nts.pressure_deviation.unwrap() > 0.05, "{nts:?}");
    let svg = std::fs::read_to_string(dir.path().join("s/accuracy.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("well-formed SVG");
    // One panel (only the patch measure has values): the root and one nested <svg>.
    let panels = doc.descendants().filter(|n| n.has_tag_name("svg")).count();
    assert_eq!(panels, 2, "root + 1 panel");
    assert!(svg.contains("patch test"), "the panel names its measure");
    assert!(svg.contains("rate "), "legend carries the fitted rate");

    // An existing study.csv is not replaced without --overwrite (exit 1, file unchanged) ...
    let before = std::fs::read(&csv).unwrap();
    let o = signorini(&args, dir.path());
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--overwrite"));
    assert_eq!(std::fs::read(&csv).unwrap(), before);
    // ... and is with it.
    let mut again = args.to_vec();
    again.push("--overwrite");
    let o = signorini(&again, dir.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn study_refuses_a_scene_without_reference_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(fixture("patch.toml")).unwrap();
    let cut = text.find("[reference]").unwrap();
    std::fs::write(dir.path().join("plain.toml"), &text[..cut]).unwrap();
    let o = signorini(
        &["study", "plain.toml", "--hmax", "0.2", "--out", "s"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("[reference]"), "{stderr}");
    assert!(!dir.path().join("s").exists(), "nothing written");
}

#[test]
fn study_refuses_unknown_formulations_meshes_and_elements() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("patch.toml");
    let scene = scene.to_str().unwrap();
    for (flag, value, says) in [
        ("--formulations", "penalty", "node-to-segment or mortar"),
        ("--meshes", "adaptive", "uniform or graded"),
        ("--elements", "p2", "p1 or q1"),
    ] {
        let o = signorini(
            &["study", scene, "--hmax", "0.2", flag, value, "--out", "s"],
            dir.path(),
        );
        assert_eq!(o.status.code(), Some(1), "{flag} {value}");
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(stderr.contains(says), "{stderr}");
    }
}

#[test]
fn check_accepts_every_accuracy_fixture() {
    let dir = fixture("");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let o = signorini(&["check", path.to_str().unwrap()], Path::new("."));
            assert!(
                o.status.success(),
                "{}: {}",
                path.display(),
                String::from_utf8_lossy(&o.stderr)
            );
            let scene = Scene::from_path(&path).unwrap();
            assert!(
                scene.reference.is_some(),
                "{}: no [reference]",
                path.display()
            );
            n += 1;
        }
    }
    assert_eq!(n, 4, "hertz, hertz-graded, patch, cattaneo");
}

/// A point that cannot be run is written with status `error` and its message, the others are
/// still solved, and the exit code is 2 (as for sweep).  hmax 0.005 asks for ~2 × 10⁵ triangles
/// per block, past `--max-elements 20000`: the preflight refuses that point only.
#[test]
fn a_point_that_fails_is_recorded_and_the_exit_code_is_2() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("patch.toml");
    let o = signorini(
        &[
            "study",
            scene.to_str().unwrap(),
            "--hmax",
            "0.1,0.005",
            "--formulations",
            "mortar",
            "--meshes",
            "uniform",
            "--elements",
            "p1",
            "--max-elements",
            "20000",
            "--out",
            "s",
        ],
        dir.path(),
    );
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let points = read_points(&dir.path().join("s/study.csv")).unwrap();
    assert_eq!(points.len(), 2);
    assert_eq!(points[0].status, "solved");
    assert_eq!(points[1].status, "error");
    assert!(points[1].message.contains("elements"), "{:?}", points[1]);
    assert!(points[1].pressure_deviation.is_none());
    assert!(String::from_utf8_lossy(&o.stderr).contains("1 of 2 points not solved"));
    assert!(dir.path().join("s/accuracy.svg").is_file());
}
