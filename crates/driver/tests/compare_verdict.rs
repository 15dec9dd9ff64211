//! One verdict everywhere: `compare` calls a backend's answer `solved` exactly when `solve` does
//! (the same check, derived numbers included); compare says when its floor factored A + εI; and
//! `timing_s.total` of result.json covers the phases docs/scene.md names.
#![allow(clippy::unwrap_used)]

mod common;
use common::{blocks, json, repo, signorini};

use std::path::Path;

/// `compare`'s status per backend and `solve`'s for each of `backends` on `scene`, run in a
/// fresh directory `dir` (`error` for a solve that could not run and wrote nothing).
fn statuses(dir: &Path, scene: &str, backends: &[&str]) -> Vec<(String, String, String)> {
    std::fs::create_dir_all(dir).unwrap();
    let list = backends.join(",");
    let o = signorini(
        &["compare", scene, "--backends", &list, "--out", "cmp"],
        dir,
    );
    assert!(
        matches!(o.status.code(), Some(0 | 2)),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let report = json(&dir.join("cmp/compare.json"));
    backends
        .iter()
        .zip(report["backends"].as_array().unwrap())
        .map(|(b, row)| {
            let out = format!("res-{b}");
            let o = signorini(&["solve", scene, "--backend", b, "--out", &out], dir);
            let result = dir.join(&out).join("result.json");
            let solved = if result.exists() {
                json(&result)["status"].as_str().unwrap().to_string()
            } else {
                "error".to_string()
            };
            // solve's exit code says the same as its file (0 exactly when solved).
            assert_eq!(o.status.code() == Some(0), solved == "solved", "{b}");
            let compared = row["status"].as_str().unwrap().to_string();
            (b.to_string(), compared, solved)
        })
        .collect()
}

/// E = 1e290 under a traction of 1e155: displacements (~1e-135), multipliers (~1e155) and the
/// objective (~1e20) are finite, so the core's check passes, but the von Mises stress squares
/// σ ≈ 1e155 and overflows: `solve` says `numerical-error`.  compare used to say `solved` (it
/// skipped the derived numbers' check).
#[test]
fn compare_refuses_what_solve_refuses_derived_numbers_included() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), blocks("1e290", "-1e155", "0")).unwrap();
    let rows = statuses(dir.path(), "s.toml", &["clarabel", "dual-ssn", "pdas"]);
    for (backend, compared, solved) in &rows {
        assert_eq!(compared, solved, "{backend}: compare ≠ solve");
    }
    // The scene does reach the derived-number check: solve refuses it for that reason.
    assert!(
        rows.iter().all(|(_, _, s)| s == "numerical-error"),
        "{rows:?}"
    );
    let r = json(&dir.path().join("res-pdas/result.json"));
    assert!(
        r["message"].as_str().unwrap().contains("not finite"),
        "{}",
        r["message"]
    );
    let c = json(&dir.path().join("cmp/compare.json"));
    assert!(c["backends"][0]["message"]
        .as_str()
        .unwrap()
        .contains("not finite"));
}

/// On the committed fixtures, compare's status per backend is solve's (solved or not alike).
#[test]
fn compare_and_solve_agree_on_fixtures() {
    let dir = tempfile::tempdir().unwrap();
    for (i, fixture) in [
        "fixtures/seed/exp1.toml",
        "fixtures/hard/floating.toml",
        "fixtures/hard/floating-free.toml",
        "fixtures/hard/stiffness-contrast.toml",
    ]
    .into_iter()
    .enumerate()
    {
        let scene = repo(fixture);
        let rows = statuses(
            &dir.path().join(i.to_string()),
            scene.to_str().unwrap(),
            &["clarabel", "dual-ssn", "pdas", "dual-pgs"],
        );
        for (backend, compared, solved) in rows {
            assert_eq!(compared, solved, "{fixture}, {backend}: compare ≠ solve");
        }
    }
}

/// A block held only by contact makes A singular: the floor factors A + εI, ε = 1e-8 · max Aⱼⱼ,
/// and compare.json and the table say so; on a clamped scene neither does.
#[test]
fn a_regularised_floor_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let floating = repo("fixtures/hard/floating.toml");
    let o = signorini(
        &[
            "compare",
            floating.to_str().unwrap(),
            "--backends",
            "clarabel",
            "--out",
            "f",
        ],
        dir.path(),
    );
    let table = String::from_utf8_lossy(&o.stdout).into_owned();
    assert_eq!(o.status.code(), Some(0), "{table}");
    let eps = json(&dir.path().join("f/compare.json"))["floor_regularised"]
        .as_f64()
        .expect("floor_regularised written");
    // ε = 1e-8 · max Aⱼⱼ in A's units, A assembled here independently of compare; the floor
    // shifts the scaled Â = A / k̄, so ε comes back through two roundings (≤ 1e-15 relative).
    let scene = signorini::run::load_scene(Some(&floating)).unwrap();
    let qp = signorini::run::prepare(&scene, &Default::default())
        .unwrap()
        .qp;
    let max_diag = (0..qp.dofs())
        .map(|j| *qp.stiffness.get(j, j).unwrap())
        .fold(0.0, f64::max);
    let want = 1e-8 * max_diag;
    assert!((eps - want).abs() <= 1e-14 * want, "{eps} vs {want}");
    assert!(table.contains("A + εI*"), "{table}");
    assert!(table.contains("* the floor factored A + εI"), "{table}");
    let o = signorini(
        &["compare", "--backends", "clarabel", "--out", "c"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(0));
    let c = json(&dir.path().join("c/compare.json"));
    assert!(c.get("floor_regularised").is_none(), "{c}");
    assert!(!String::from_utf8_lossy(&o.stdout).contains("εI"));
}

/// `timing_s.total` covers what docs/scene.md says: meshing, assembly and the solve (and the
/// output fields), so it is at least their sum; and it lies within the process's wall time.
#[test]
fn the_total_time_covers_the_phases_it_names() {
    let dir = tempfile::tempdir().unwrap();
    let start = std::time::Instant::now();
    let o = signorini(&["solve", "--out", "res"], dir.path());
    let wall = start.elapsed().as_secs_f64();
    assert_eq!(o.status.code(), Some(0));
    let t = &json(&dir.path().join("res/result.json"))["timing_s"];
    let phase = |k: &str| t[k].as_f64().unwrap();
    let total = phase("total");
    let sum = phase("mesh") + phase("assemble") + phase("solve");
    // Each phase is a separate clock reading inside the total's span; their sum can exceed the
    // total only by round-off of the three additions (≤ 3 ulps of the total).
    assert!(total >= sum * (1.0 - 4.0 * f64::EPSILON), "{total} < {sum}");
    assert!(total <= wall, "{total} > the process's {wall}");
}
