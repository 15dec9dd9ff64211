//! Memory guards through the binary, with the limit forced small by `SIGNORINI_MEMORY_LIMIT`:
//! every backend refuses cleanly (exit 3 naming the GiB, nothing written; in `compare` an
//! `error` row), a bad limit is a usage error naming the variable, and `check` names each
//! backend's need.  The limits are computed from the same estimates the binary uses
//! ([`signorini::check::memory_needs`]) in this process, where the variable is not set.
#![allow(clippy::unwrap_used)]

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use signorini::check::{memory_needs, MemoryNeeds};
use signorini::guard::RunShape;
use signorini_core::memory::LIMIT_VAR;
use signorini_core::mesh::MeshLimits;
use signorini_core::scene::Scene;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/hard")
        .join(name)
}

/// The long clamped strip: 301 contact rows on ~5 000 DOFs, so that the dense m × m arrays of
/// the dual forms outgrow the sparse factor of A.
fn strip() -> PathBuf {
    fixture("strip-thin-clamped.toml")
}

/// `signorini args` with the memory limit set to `limit` (only in the child).
fn limited(limit: &str, args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
        .args(args)
        .env(LIMIT_VAR, limit)
        .current_dir(cwd)
        .output()
        .unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The entries of `dir` (a refused run leaves none, not even a staging directory).
fn entries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .map(|d| {
            d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default()
}

/// The estimates for `scene` as `check` makes them.
fn needs_of(scene: &Path) -> MemoryNeeds {
    let scene = Scene::from_path(scene).unwrap();
    let prepared = signorini::run::prepare(&scene, &MeshLimits::default()).unwrap();
    memory_needs(&prepared.model, &prepared.qp).unwrap()
}

/// The run's peak with `backend` as the binary prices it under a limit of `limit` bytes (the
/// estimate of dual-ssn and auto depends on what is available).
fn need_under(scene: &Path, backend: &str, limit: Option<u64>) -> f64 {
    let scene = Scene::from_path(scene).unwrap();
    let prepared = signorini::run::prepare(&scene, &MeshLimits::default()).unwrap();
    let mut shape = RunShape::of(&prepared.model, &prepared.qp).unwrap();
    shape.available = limit;
    shape.need(backend.parse().unwrap()).unwrap().bytes
}

/// The figure both `check` and `solve` print for a need: MiB with one decimal.
fn mib(bytes: f64) -> String {
    format!("{:.1} MiB", bytes / (1024.0 * 1024.0))
}

/// `solve --backend b` under `limit`: its exit code and stderr (the output directory in a
/// temporary directory; a refusal must leave it absent).
fn solve_under(limit: u64, scene: &Path, backend: &str) -> (Option<i32>, String, Vec<String>) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = limited(
        &limit.to_string(),
        &[
            "solve",
            scene.to_str().unwrap(),
            "--backend",
            backend,
            "--out",
            out.to_str().unwrap(),
        ],
        dir.path(),
    );
    (o.status.code(), text(&o.stderr), entries(&out))
}

/// `check`'s line for `backend` under `limit`.
fn check_line(limit: u64, scene: &Path, backend: &str) -> String {
    let o = limited(
        &limit.to_string(),
        &["check", scene.to_str().unwrap()],
        Path::new("."),
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    text(&o.stdout)
        .lines()
        .find(|l| l.trim_start().starts_with(&format!("{backend} ")))
        .unwrap_or_else(|| panic!("no line for {backend}"))
        .to_string()
}

/// Each guard fires, and `check` and `solve` agree on it: one byte below the run's peak as
/// `check` prices it, `check` says "does not fit" and `solve` refuses with exit 3, the same
/// figure and nothing written; one byte above, `check` says it fits and `solve` runs (exit 0 or
/// 2: solved or not, but not refused — no allocation check of the backend's own refuses what the
/// guard let through).  The figures are exact: the same code on the same scene in this process.
fn guard_agrees(scene: &Path, backend: &str) {
    // dual-ssn prices its matrix-free steps when the dense ones do not fit, auto the members
    // that fit: below a figure the figure may be a smaller one, so descend to the figure that
    // stays when the limit is one byte below it.
    let mut need = need_under(scene, backend, None);
    for _ in 0..10 {
        let next = need_under(scene, backend, Some(need as u64 - 1));
        if next >= need {
            break;
        }
        need = next;
    }
    let below = need as u64 - 1;
    let line = check_line(below, scene, backend);
    assert!(
        line.contains("[does not fit]") && line.contains(&mib(need)),
        "{backend} below: {line}"
    );
    let (code, err, written) = solve_under(below, scene, backend);
    assert_eq!(code, Some(3), "{backend} below: {err}");
    assert!(
        err.contains(&mib(need)),
        "{backend}: {err} lacks {}",
        mib(need)
    );
    assert!(written.is_empty(), "{backend} wrote {written:?}");
    let above = need as u64 + 1;
    let line = check_line(above, scene, backend);
    assert!(!line.contains("[does not fit]"), "{backend} above: {line}");
    let (code, err, _) = solve_under(above, scene, backend);
    assert!(
        matches!(code, Some(0 | 2)),
        "{backend} above: {code:?} {err}"
    );
}

#[test]
fn check_and_solve_agree_on_the_run_of_each_backend_family() {
    let scene = strip();
    for backend in ["dual-pgs", "dual-ssn", "pdas", "clarabel"] {
        guard_agrees(&scene, backend);
    }
}

/// The case: at 16.5 MiB `check` said dual-pgs does not fit (17.6 MiB) while `solve`
/// ran it, its factor of A and its dense H each checked alone.  Now `solve` refuses what `check`
/// refuses.
#[test]
fn the_sum_is_checked_not_each_allocation() {
    let scene = strip();
    let need = need_under(&scene, "dual-pgs", None);
    // Below the sum but above each part: the factor of A with the problem, and H alone.
    let limit = (need * 0.9) as u64;
    let (code, err, written) = solve_under(limit, &scene, "dual-pgs");
    assert_eq!(code, Some(3), "{err}");
    assert!(written.is_empty());
}

/// With friction the solve path holds a second copy of the problem (Coulomb's), and auto's
/// chain is priced by its walk: the guard fires for both on the frictional fixture too.
#[test]
fn the_frictional_run_and_auto_are_guarded_alike() {
    let scene = fixture("friction-stick.toml");
    for backend in ["dual-pgs", "auto"] {
        guard_agrees(&scene, backend);
    }
}

fn need(needs: &MemoryNeeds, backend: &str) -> f64 {
    needs
        .backends
        .iter()
        .find(|n| n.backend == backend)
        .unwrap_or_else(|| panic!("no estimate for {backend}"))
        .bytes
}

/// Asserts `solve --backend b` exits 3 naming the GiB (and `also`), writing nothing.
fn solve_refused(limit: &str, scene: &Path, backend: &str, also: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = limited(
        limit,
        &[
            "solve",
            scene.to_str().unwrap(),
            "--backend",
            backend,
            "--out",
            out.to_str().unwrap(),
        ],
        dir.path(),
    );
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{backend}: {err}");
    assert!(
        err.contains("GiB") && err.contains(also),
        "{backend}: {err}"
    );
    assert!(
        entries(&out).is_empty(),
        "{backend} wrote {:?}",
        entries(&out)
    );
    assert!(
        entries(dir.path()).iter().all(|e| e == "out"),
        "{backend} left {:?}",
        entries(dir.path())
    );
}

/// Every backend in both forms, and the chain.
const EVERY_BACKEND: [&str; 9] = [
    "auto",
    "clarabel",
    "clarabel/dual",
    "osqp",
    "osqp/dual",
    "dual-pgs",
    "dual-uzawa",
    "dual-ssn",
    "pdas",
];

#[test]
fn a_limit_that_is_not_a_size_is_a_usage_error_naming_the_variable() {
    let dir = tempfile::tempdir().unwrap();
    for bad in ["lots", "-1G", "12X", ""] {
        let o = limited(bad, &["solve", "--out", "out"], dir.path());
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{bad:?}: {err}");
        assert!(err.contains(LIMIT_VAR), "{bad:?}: {err}");
        assert!(entries(dir.path()).is_empty(), "{bad:?}");
    }
}

/// Below what every run holds (the factor of A, ~1 MiB here), every backend is refused before
/// it starts: exit 3, the GiB named, nothing written; `compare` likewise.
#[test]
fn under_a_tiny_limit_every_backend_is_refused_and_nothing_is_written() {
    let scene = strip();
    for backend in EVERY_BACKEND {
        solve_refused("64K", &scene, backend, "GiB");
    }
    let dir = tempfile::tempdir().unwrap();
    let o = limited(
        "64K",
        &[
            "compare",
            scene.to_str().unwrap(),
            "--backends",
            &EVERY_BACKEND[1..].join(","),
            "--out",
            "out",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(3), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("GiB"));
    assert!(entries(&dir.path().join("out")).is_empty());
}

/// Just above what every run holds, the backends whose runs are larger are refused: by `solve`'s
/// guard of the run's peak (naming their KKT factors, the condensed-dual forms' dense H), and in
/// `compare` by their own allocation checks, each an `error` row naming the GiB; the backend
/// that fits (dual-uzawa, no dense matrix) still solves.
#[test]
fn just_above_the_factor_of_a_each_backend_guards_its_own_allocation() {
    let scene = strip();
    let needs = needs_of(&scene);
    // 5 % above the base: the prepare check passes; every backend below needs more.
    let limit = (needs.base * 1.05) as u64;
    let refusing = ["clarabel", "osqp", "clarabel/dual", "osqp/dual"];
    for backend in refusing {
        assert!(
            need(&needs, backend) > limit as f64,
            "{backend}: {} ≤ {limit}: the scene does not separate it",
            need(&needs, backend)
        );
    }
    let limit = limit.to_string();
    for backend in ["clarabel", "osqp"] {
        solve_refused(&limit, &scene, backend, "KKT");
    }
    for backend in ["clarabel/dual", "osqp/dual"] {
        solve_refused(&limit, &scene, backend, "condensed dual H");
    }
    let dir = tempfile::tempdir().unwrap();
    let o = limited(
        &limit,
        &[
            "compare",
            scene.to_str().unwrap(),
            "--backends",
            "clarabel,osqp,clarabel/dual,osqp/dual,dual-uzawa",
            "--out",
            "out",
        ],
        dir.path(),
    );
    // Not every backend solved: exit 2, the files written.
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    let report: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("out/compare.json")).unwrap(),
    )
    .unwrap();
    let rows = report["backends"].as_array().unwrap();
    for row in rows {
        let backend = row["backend"].as_str().unwrap();
        let status = row["status"].as_str().unwrap();
        if backend == "dual-uzawa" {
            assert_ne!(status, "error", "{row}");
        } else {
            assert_eq!(status, "error", "{row}");
            assert!(row["message"].as_str().unwrap().contains("GiB"), "{row}");
        }
    }
    assert_eq!(rows.len(), 5);
}

/// `check` prints every backend's need and names the largest: osqp's two KKT factors exceed
/// clarabel's one (the same K, priced twice), so on a sparse scene osqp is the largest unless a
/// dense dual outgrows it.
#[test]
fn check_names_every_backends_need_and_the_largest() {
    let scene = strip();
    let o = common::signorini(&["check", scene.to_str().unwrap()], Path::new("."));
    let out = text(&o.stdout);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for backend in EVERY_BACKEND.iter().filter(|b| **b != "auto") {
        assert!(
            out.lines().any(|l| l.trim_start().starts_with(backend)),
            "{backend} missing in {out}"
        );
    }
    let needs = needs_of(&scene);
    let largest = needs.largest().unwrap();
    assert!(needs.backends.iter().all(|n| n.bytes <= largest.bytes));
    assert!(need(&needs, "osqp") > need(&needs, "clarabel"));
    assert!(
        out.contains(&format!("largest memory need: {} (", largest.backend)),
        "{out}"
    );
}
