//! Gmsh meshes (issue 11, item 1): the Hertz cylinder on a block read from Gmsh files
//! (fixtures/gmsh/, made by make_meshes.py) against the same geometry meshed internally and
//! against Johnson's formulas; the binary and ASCII files of one mesh give identical results;
//! the CLI solves the fixture and refuses a bad mesh naming the file.

#![allow(clippy::unwrap_used)]

use std::path::PathBuf;
use std::process::Command;

use signorini::auto::AutoBackend;
use signorini::run::{self, Outcome};
use signorini_core::accuracy::accuracy;
use signorini_core::mesh::MeshLimits;
use signorini_core::qp::{QpStatus, SolveOptions};
use signorini_core::scene::Scene;

fn fixture(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fixtures/{path}"))
}

fn solve(scene: &Scene) -> Outcome {
    let mut backend = AutoBackend::default();
    let o = run::solve_scene(
        scene,
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
    o
}

fn max_u(o: &Outcome, body: &str) -> f64 {
    o.report
        .bodies
        .iter()
        .find(|b| b.name == body)
        .unwrap()
        .max_displacement
}

/// Johnson's Hertz line contact (see crates/driver/tests/accuracy.rs): E* = E / (2(1 − ν²)),
/// a = √(4PR/(πE*)), from the load the run applied.
fn johnson_half_width(load: f64) -> f64 {
    let (e, nu, r) = (1.0_f64, 0.3_f64, 1.0_f64);
    let e_star = e / (2.0 * (1.0 - nu * nu));
    (4.0 * load * r / (std::f64::consts::PI * e_star)).sqrt()
}

#[test]
fn gmsh_hertz_matches_internal_mesh_and_johnson() {
    let gmsh = Scene::from_path(&fixture("gmsh/hertz.toml")).unwrap();
    let internal = Scene::from_path(&fixture("accuracy/hertz-graded.toml")).unwrap();
    let (g, i) = (solve(&gmsh), solve(&internal));

    // The load: the traction on the group "top" (the cap's flat top, width 2√(1 − 0.4²)).
    let cap = g.report.bodies.iter().find(|b| b.name == "cap").unwrap();
    let load = -cap.applied[1];
    let width = 2.0 * (1.0_f64 - 0.16).sqrt();
    assert!(
        (load / (0.0005885574526504614 * width) - 1.0).abs() < 1e-12,
        "load {load:e}"
    );
    // Same load on both scenes, exactly (the group and the box select the same top side).
    let cap_i = i.report.bodies.iter().find(|b| b.name == "cap").unwrap();
    assert!((cap_i.applied[1] / cap.applied[1] - 1.0).abs() < 1e-12);

    // Contact force: the cap is held in y by contact alone, so Σλ is the load up to mortar's
    // normal tilt (≤ (a/R)²/2 = 0.125 %), on either mesh.
    let force = g.report.contacts[0].normal_force;
    assert!(
        force >= load * (1.0 - 1e-6) && force <= load * (1.0 + 0.00125),
        "{force:e} vs {load:e}"
    );
    let force_i = i.report.contacts[0].normal_force;
    assert!(
        (force / force_i - 1.0).abs() < 0.00125,
        "{force:e} vs {force_i:e}"
    );
    // The block's support reaction carries the load down (equilibrium, round-off only).
    let block = g.report.bodies.iter().find(|b| b.name == "block").unwrap();
    assert!((block.reaction[1] / load - 1.0).abs() < 1e-6);

    // Max displacement: the cap's top moves by the compliance of both bodies (dominated by the
    // far field, element size 0.08 in the Gmsh meshes against 0.016 internally) plus the contact
    // approach.  P1 displacement errors go as h² in the bulk: (0.08 / 0.7)² ≈ 1.3 % for a body of
    // size ~0.7, so 3 % is allowed between the two meshes.
    for body in ["cap", "block"] {
        let (ug, ui) = (max_u(&g, body), max_u(&i, body));
        println!("{body}: max |u| gmsh {ug:e}, internal {ui:e}");
        assert!((ug / ui - 1.0).abs() < 0.03, "{body}: {ug:e} vs {ui:e}");
    }

    // Hertz half-width, from the second moment of the contact forces: with elements of a/10 at
    // the contact, the moment half-width of mortar is within 1 % at a/8 on graded internal
    // meshes (crates/driver/tests/accuracy.rs); a/10 here, with Gmsh's unstructured mesh, so
    // 3 % is allowed.  The finite bodies add O((a/depth)²) ≈ 0.4 % (fixtures/accuracy/hertz.toml).
    let reference = gmsh.reference.clone().unwrap();
    let acc = accuracy(&reference, &g.report).unwrap();
    let a = acc.half_width.unwrap();
    let a_johnson = johnson_half_width(load);
    assert!((reference.half_width.unwrap() / a_johnson - 1.0).abs() < 1e-9);
    println!(
        "half-width {} (Johnson {a_johnson}), error {:.3} %",
        a.computed,
        100.0 * a.error()
    );
    assert!(a.error().abs() < 0.03, "half-width error {}", a.error());
    // And the internally meshed scene agrees with it within the same bound.
    let a_i = accuracy(&reference, &i.report).unwrap().half_width.unwrap();
    assert!((a.computed / a_i.computed - 1.0).abs() < 0.03);
}

#[test]
fn binary_and_ascii_meshes_give_identical_results() {
    let ascii = Scene::from_path(&fixture("gmsh/hertz.toml")).unwrap();
    let text = std::fs::read_to_string(fixture("gmsh/hertz.toml"))
        .unwrap()
        .replace("mesh = \"cap.msh\"", "mesh = \"cap-binary.msh\"");
    assert!(text.contains("cap-binary.msh"));
    let binary = Scene::from_toml_in(&text, &fixture("gmsh")).unwrap();
    let (ma, mb) = (
        &ascii.bodies[0].imported.as_ref().unwrap().mesh,
        &binary.bodies[0].imported.as_ref().unwrap().mesh,
    );
    // Same elements and boundary; coordinates equal to the last digits: Gmsh writes ASCII
    // coordinates with 16 significant digits (%.16g), binary ones with all 17, so they differ
    // by at most 1e-16 × the coordinate (≤ 2e-16 here).
    assert!(ma.cells == mb.cells, "same elements");
    assert!(ma.boundary == mb.boundary, "same boundary");
    assert_eq!(ma.nodes.len(), mb.nodes.len());
    let worst = ma
        .nodes
        .iter()
        .zip(&mb.nodes)
        .map(|(p, q)| (p[0] - q[0]).abs().max((p[1] - q[1]).abs()))
        .fold(0.0, f64::max);
    assert!(worst <= 1e-15, "coordinates differ by {worst:e}");
    // So the results agree to round-off: a 1e-16 relative perturbation of the geometry, times a
    // condition number of the stiffness well below 1e6 at 6 k DOFs, stays far below 1e-9 (the
    // solve's KKT tolerance); and both solves run the same backend with the same active set.
    let (a, b) = (solve(&ascii), solve(&binary));
    assert_eq!(a.solution.backend, b.solution.backend);
    let scale = a
        .solution
        .displacement
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    let du = a
        .solution
        .displacement
        .iter()
        .zip(&b.solution.displacement)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(
        du <= 1e-9 * scale,
        "displacements differ by {du:e} (scale {scale:e})"
    );
    let (fa, fb) = (
        a.report.contacts[0].normal_force,
        b.report.contacts[0].normal_force,
    );
    assert!((fa / fb - 1.0).abs() < 1e-9, "{fa:e} vs {fb:e}");
    assert_eq!(a.report.contacts[0].active, b.report.contacts[0].active);
}

#[test]
fn cli_solves_the_gmsh_fixture_and_refuses_a_missing_group() {
    let dir = std::env::temp_dir().join(format!("signorini-gmsh-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_signorini"))
        .args(["check", fixture("gmsh/hertz.toml").to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // A scene beside copies of the meshes, naming a group that block.msh does not define.
    for f in ["cap.msh", "block.msh"] {
        std::fs::copy(fixture(&format!("gmsh/{f}")), dir.join(f)).unwrap();
    }
    let text = std::fs::read_to_string(fixture("gmsh/hertz.toml"))
        .unwrap()
        .replace("group = \"bottom\"", "group = \"base\"");
    std::fs::write(dir.join("scene.toml"), text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_signorini"))
        .args(["check", "scene.toml"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("\"base\"") && err.contains("block.msh") && err.contains("\"bottom\""),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A sweep changes hmax, which a body meshed by Gmsh does not have: every point would repeat
/// the same mesh, so the plan is refused (exit 1, naming the body) before anything is written.
#[test]
fn sweep_refuses_to_sweep_a_mesh_body() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("gmsh/hertz.toml");
    let o = Command::new(env!("CARGO_BIN_EXE_signorini"))
        .args([
            "sweep",
            scene.to_str().unwrap(),
            "--hmax",
            "0.1,0.05",
            "--backends",
            "clarabel",
            "--out",
            "s",
        ])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("takes its mesh from a file"), "{err}");
    assert!(!dir.path().join("s").exists());
}
