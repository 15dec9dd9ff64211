//! `signorini sweep`: points written as they finish, `--resume` skipping them, the error
//! columns meaning what they say, and a refined mesh converging; existing results never lost,
//! `--resume` refusing a file that is not this sweep's, and failed points giving exit code 2.

mod common;
use common::signorini;

use std::path::{Path, PathBuf};

use signorini::sweep::read_points;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fixtures/seed/{name}.toml"))
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
    let hash = &points[0].scene_hash;
    assert_eq!(hash.len(), 16, "{hash}");
    for p in &points {
        assert_eq!(&p.scene_hash, hash);
        assert_eq!(p.status, "solved", "{p:?}");
        assert!(p.floor_s > 0.0 && p.solve_s > 0.0);
        assert!((p.ratio_to_floor - p.solve_s / p.floor_s).abs() <= 1e-12 * p.ratio_to_floor);
        // L has its diagonal at least, the dense lower triangle at most.
        assert_eq!(p.floor_ordering, "amd");
        assert!(p.floor_nnz_l >= p.dofs && p.floor_nnz_l <= p.dofs * (p.dofs + 1) / 2);
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
    // Backends named explicitly: the default list has osqp, which a build without the `osqp`
    // feature refuses before the plan is looked at.
    for (bad, msg) in [
        (
            vec!["--hmax", "0.2,-1", "--backends", "clarabel"],
            "positive",
        ),
        (
            vec!["--hmax", "0.2", "--tol", "2", "--backends", "clarabel"],
            "(0, 1)",
        ),
        (
            vec![
                "--hmax",
                "0.2",
                "--bodies",
                "nobody",
                "--backends",
                "clarabel",
            ],
            "nobody",
        ),
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

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs a two-point sweep of Experiment 2b (hmax 0.3 and 0.2, clarabel, tol 1e-9) into
/// `dir/s`, returning the CSV's path and bytes.
fn two_point_sweep(dir: &Path) -> (PathBuf, Vec<u8>) {
    let scene = fixture("exp2b");
    let o = signorini(
        &[
            "sweep",
            scene.to_str().expect("UTF-8 path"),
            "--hmax",
            "0.3,0.2",
            "--backends",
            "clarabel",
            "--out",
            "s",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = dir.join("s/sweep.csv");
    let bytes = std::fs::read(&csv).expect("the sweep wrote its CSV");
    (csv, bytes)
}

#[test]
fn an_existing_sweep_is_never_deleted_or_truncated() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, before) = two_point_sweep(dir.path());
    let plots: Vec<(PathBuf, Vec<u8>)> = ["time_vs_dofs.svg", "ratio_vs_dofs.svg"]
        .iter()
        .map(|n| {
            let p = dir.path().join("s").join(n);
            let b = std::fs::read(&p).unwrap();
            (p, b)
        })
        .collect();
    let scene = fixture("exp2b");
    let scene = scene.to_str().unwrap();
    let free = {
        // Experiment 2b without its contact pair: valid, but no sweep point can run.
        let text = std::fs::read_to_string(fixture("exp2b")).unwrap();
        let cut = text.find("[[contact]]").unwrap();
        let end = text.find("[[probe]]").unwrap();
        let path = dir.path().join("free.toml");
        std::fs::write(&path, format!("{}{}", &text[..cut], &text[end..])).unwrap();
        path
    };
    for (args, expect) in [
        // No flag: refused, whether the plan is good...
        (vec!["sweep", scene, "--hmax", "0.1"], "--overwrite"),
        // ...or bad (before the fix, the file was deleted first and then the plan refused).
        (vec!["sweep", scene, "--hmax", "0.3,1e-7"], "--max-elements"),
        (
            vec!["sweep", scene, "--hmax", "0.3,1e-7", "--overwrite"],
            "--max-elements",
        ),
        (
            vec!["sweep", scene, "--hmax", "0.3", "--repeat", "0"],
            "--repeat",
        ),
        (
            vec!["sweep", scene, "--hmax", "0.3", "--resume", "--overwrite"],
            "--overwrite",
        ),
        // --overwrite replaces the file only when the new sweep writes a point: here none runs.
        (
            vec![
                "sweep",
                free.to_str().unwrap(),
                "--hmax",
                "0.3",
                "--overwrite",
            ],
            "no contact constraint row",
        ),
    ] {
        let mut args = args.clone();
        args.extend(["--backends", "clarabel", "--out", "s"]);
        let o = signorini(&args, dir.path());
        assert!(!o.status.success(), "{args:?}");
        assert!(stderr(&o).contains(expect), "{args:?}: {}", stderr(&o));
        assert_eq!(std::fs::read(&csv).unwrap(), before, "{args:?}");
        for (p, b) in &plots {
            assert_eq!(&std::fs::read(p).unwrap(), b, "{args:?}: {}", p.display());
        }
    }
    // --overwrite with a good plan replaces the set: only the new grid is left.
    let o = signorini(
        &[
            "sweep",
            scene,
            "--hmax",
            "0.25",
            "--backends",
            "clarabel",
            "--overwrite",
            "--out",
            "s",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let points = read_points(&csv).unwrap();
    assert_eq!(points.len(), 1);
    assert_eq!(points[0].hmax, 0.25);
    // One mesh: no slope to fit, but the time plots are still drawn; nothing temporary is left.
    let mut names: Vec<String> = std::fs::read_dir(dir.path().join("s"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");
    assert!(names.contains(&"sweep.csv".to_string()), "{names:?}");
}

#[test]
fn resume_refuses_a_foreign_or_corrupt_file_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, good) = two_point_sweep(dir.path());
    let text = String::from_utf8(good.clone()).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 3, "{text}");
    let join = |ls: &[&str]| ls.join("\n") + "\n";
    let without_last_column = |l: &str| l.rsplit_once(',').unwrap().0.to_string();
    // scene_hash is followed by the floor's two columns (floor_ordering, floor_nnz_l).
    let without_last_columns =
        |l: &str, k: usize| (0..k).fold(l.to_string(), |l, _| without_last_column(&l));
    let exp2b = fixture("exp2b");
    let exp2c = fixture("exp2c");
    let base = ["--hmax", "0.3,0.2", "--backends", "clarabel"];
    let cases: Vec<(&str, String, Vec<&str>, &str, &str)> = vec![
        (
            "another scene",
            text.clone(),
            vec![exp2c.to_str().unwrap()],
            "line 2",
            "scene_hash",
        ),
        (
            "the last line cut short",
            text[..text.len() - 5].to_string(),
            vec![exp2b.to_str().unwrap()],
            "line 3",
            "incomplete",
        ),
        (
            "a point twice",
            join(&[lines[0], lines[1], lines[2], lines[1]]),
            vec![exp2b.to_str().unwrap()],
            "line 4",
            "repeats the point of line 2",
        ),
        (
            "a row with a field missing",
            join(&[lines[0], &without_last_column(lines[1]), lines[2]]),
            vec![exp2b.to_str().unwrap()],
            "line 2",
            "fields",
        ),
        (
            "a file without scene_hash",
            join(&[
                &without_last_columns(lines[0], 3),
                &without_last_columns(lines[1], 3),
                &without_last_columns(lines[2], 3),
            ]),
            vec![exp2b.to_str().unwrap()],
            "line 1",
            "scene_hash",
        ),
        (
            "a file without the floor's columns",
            join(&[
                &without_last_columns(lines[0], 2),
                &without_last_columns(lines[1], 2),
                &without_last_columns(lines[2], 2),
            ]),
            vec![exp2b.to_str().unwrap()],
            "line 1",
            "older version",
        ),
        (
            "an hmax outside the plan",
            text.clone(),
            vec![exp2b.to_str().unwrap(), "--hmax", "0.3"],
            "line 3",
            "hmax 0.2 is not in --hmax",
        ),
        (
            "a backend outside the plan",
            text.clone(),
            vec![exp2b.to_str().unwrap(), "--backends", "dual-pgs"],
            "line 2",
            "backend \"clarabel\"",
        ),
        (
            "a tolerance outside the plan",
            text.clone(),
            vec![exp2b.to_str().unwrap(), "--tol", "1e-6"],
            "line 2",
            "tol 1e-9",
        ),
        (
            "another set of swept bodies",
            text.clone(),
            vec![exp2b.to_str().unwrap(), "--bodies", "upper"],
            "line 2",
            "scene_hash",
        ),
    ];
    for (what, content, extra, line, reason) in cases {
        std::fs::write(&csv, &content).unwrap();
        // The case's flags replace the base's (clap appends repeated list flags).
        let mut args = vec!["sweep", extra[0]];
        for pair in base.chunks(2) {
            if !extra.contains(&pair[0]) {
                args.extend(pair);
            }
        }
        args.extend(&extra[1..]);
        args.extend(["--resume", "--out", "s"]);
        let o = signorini(&args, dir.path());
        assert!(!o.status.success(), "{what}");
        let err = stderr(&o);
        assert!(
            err.contains(&format!(
                "{}: {line}: ",
                csv.strip_prefix(dir.path()).unwrap().display()
            )) || err.contains(&format!("{line}: ")),
            "{what}: {err}"
        );
        assert!(err.contains(reason), "{what}: {err}");
        assert!(err.contains("sweep.csv"), "{what}: {err}");
        assert_eq!(std::fs::read_to_string(&csv).unwrap(), content, "{what}");
    }
    // The intact file resumes (nothing left to run) and keeps its points.
    std::fs::write(&csv, &good).unwrap();
    let mut args = vec!["sweep", exp2b.to_str().unwrap()];
    args.extend(base);
    args.extend(["--resume", "--out", "s"]);
    let o = signorini(&args, dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(read_points(&csv).unwrap().len(), 2);
}

#[test]
fn failed_points_are_written_and_exit_with_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("exp2b");
    // A time limit of a nanosecond: every backend stops at its first check.
    let o = signorini(
        &[
            "sweep",
            scene.to_str().unwrap(),
            "--hmax",
            "0.3",
            "--backends",
            "clarabel,dual-pgs",
            "--time-limit",
            "1e-9",
            "--out",
            "s",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("0 of 2 points solved, 2 not solved"), "{err}");
    assert_eq!(
        err.lines().filter(|l| l.contains("points solved")).count(),
        1
    );
    let points = read_points(&dir.path().join("s/sweep.csv")).unwrap();
    assert_eq!(points.len(), 2);
    assert!(
        points.iter().all(|p| p.status == "time-limit"),
        "{points:?}"
    );

    // A time limit too large for a duration means no limit (it used to panic).
    let o = signorini(
        &[
            "sweep",
            scene.to_str().unwrap(),
            "--hmax",
            "0.3",
            "--backends",
            "clarabel",
            "--time-limit",
            "1e20",
            "--out",
            "t",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    assert!(dir.path().join("t/sweep.csv").is_file());
}

/// A graded body keeps its grading along a sweep: `with_hmax` scales every `[[body.refine]]`
/// size by the body's factor, and the plan's element estimate counts the refined region — a
/// refine box at 1/50 of hmax makes a plan that the uniform estimate would accept exceed
/// `--max-elements` (uniform 2 × 1 block at hmax 0.1: ~60 triangles; the 0.4 × 0.1 box at 0.002
/// alone holds ~0.04 / (0.35 · 0.002²) ≈ 29 000).
#[test]
fn sweep_scales_refined_regions_and_counts_them_in_the_plan() {
    let text = r#"
        [[body]]
        name = "block"
        polygon = [[0, 0], [2, 0], [2, 1], [0, 1]]
        hmax = 0.1
        young = 1.0
        poisson = 0.3
        [[body.refine]]
        region = [0.8, 1.2, 0.9, 1.0]
        hmax = 0.002
        [[dirichlet]]
        body = "block"
        region = [0, 2, 0, 0]
    "#;
    let scene = signorini_core::scene::Scene::from_toml(text).unwrap();
    let s = signorini::sweep::with_hmax(&scene, &[], 0.05);
    assert_eq!(s.bodies[0].hmax, 0.05);
    assert!((s.bodies[0].refine[0].hmax - 0.001).abs() < 1e-15);

    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("graded.toml"), text).unwrap();
    let o = signorini(
        &[
            "sweep",
            "graded.toml",
            "--hmax",
            "0.1",
            "--backends",
            "clarabel",
            "--max-elements",
            "5000",
            "--out",
            "s",
        ],
        dir.path(),
    );
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--max-elements"), "{}", stderr(&o));
    assert!(!dir.path().join("s/sweep.csv").exists());
}
