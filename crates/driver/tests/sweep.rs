//! `signorini sweep`: points appended as they finish, `--resume` skipping them, the error
//! columns meaning what they say, and a refined mesh converging.

use std::path::{Path, PathBuf};
use std::process::Command;

use signorini::sweep::read_points;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fixtures/seed/{name}.toml"))
}

fn signorini(args: &[&str], cwd: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run signorini")
}

#[test]
fn sweep_writes_every_point_and_resume_skips_them() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("exp3-both-h0.08");
    let args = [
        "sweep",
        scene.to_str().unwrap(),
        "--hmax",
        "0.3,0.15",
        "--backends",
        "clarabel,dual-pgs",
        "--tol",
        "1e-5,1e-9",
        "--out",
        "s",
    ];
    let o = signorini(&args, dir.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = dir.path().join("s/sweep.csv");
    let points = read_points(&csv).unwrap();
    assert_eq!(points.len(), 2 * 2 * 2);
    let header = std::fs::read_to_string(&csv).unwrap();
    assert!(header.starts_with(
        "hmax,dofs,constraints,backend,tol,status,iterations,mesh_s,assemble_s,solve_s,floor_s,ratio_to_floor,error_vs_reference"
    ));
    for p in &points {
        assert_eq!(p.status, "solved", "{p:?}");
        assert!(p.floor_s > 0.0 && p.solve_s > 0.0);
        assert!((p.ratio_to_floor - p.solve_s / p.floor_s).abs() <= 1e-12 * p.ratio_to_floor);
        let err = p.error_vs_reference.expect("reference known");
        // Each point meets its tolerance, so it is that close to the tightest answer (with a
        // margin: the tolerance bounds residuals, not the error itself).
        assert!(err <= 1e3 * p.tol, "{p:?}");
        assert!(p.error_vs_finest.is_some());
        assert!(p.peak_rss_mb > 0.0);
        assert!(p.probes.contains("top-right"));
    }
    // The finer mesh has more unknowns; the coarse one differs from it by discretisation error.
    let coarse = points.iter().find(|p| p.hmax == 0.3).unwrap();
    let fine = points.iter().find(|p| p.hmax == 0.15).unwrap();
    assert!(fine.dofs > coarse.dofs);
    assert!(coarse.error_vs_finest.unwrap() > 1e-4);
    assert!(coarse.error_vs_finest.unwrap() < 0.3);

    // Simulate an interruption: drop the last two rows, then resume.
    let text = std::fs::read_to_string(&csv).unwrap();
    let kept: Vec<&str> = text.lines().take(1 + 6).collect();
    std::fs::write(&csv, kept.join("\n") + "\n").unwrap();
    let mut resume = args.to_vec();
    resume.push("--resume");
    let o = signorini(&resume, dir.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let again = read_points(&csv).unwrap();
    assert_eq!(again.len(), 8);
    // The six kept rows are unchanged apart from error_vs_finest, which is recomputed.
    for (a, b) in points.iter().take(6).zip(&again) {
        assert_eq!(
            (a.hmax, &a.backend, a.tol, a.solve_s),
            (b.hmax, &b.backend, b.tol, b.solve_s)
        );
    }
}

#[test]
fn sweep_refuses_bad_plans_before_writing() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("exp2b");
    for (bad, msg) in [
        (vec!["--hmax", "0.2,-1"], "positive"),
        (vec!["--hmax", "0.2", "--tol", "2"], "(0, 1)"),
        (vec!["--hmax", "0.2", "--bodies", "nobody"], "nobody"),
        (vec!["--hmax", "0.2", "--backends", "magic"], "magic"),
    ] {
        let mut args = vec!["sweep", scene.to_str().unwrap(), "--out", "s"];
        args.extend(bad);
        let o = signorini(&args, dir.path());
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(msg), "{err}");
        assert!(!dir.path().join("s/sweep.csv").exists());
    }
}
