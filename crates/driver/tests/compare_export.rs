//! `signorini compare` and `signorini export` end to end: every backend on one QP, and the
//! exported Matrix Market files read back equal to the problem they came from.

mod common;
use common::signorini;

use std::path::{Path, PathBuf};

use signorini::run;
use signorini_core::mesh::MeshLimits;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fixtures/seed/{name}.toml"))
}

fn read_dense(path: &Path) -> Vec<f64> {
    let text = std::fs::read_to_string(path).expect("read");
    let mut lines = text.lines().filter(|l| !l.starts_with('%'));
    let header: Vec<usize> = lines
        .next()
        .expect("size line")
        .split_whitespace()
        .map(|t| t.parse().expect("size"))
        .collect();
    let v: Vec<f64> = lines.map(|l| l.trim().parse().expect("value")).collect();
    assert_eq!(header, vec![v.len(), 1]);
    v
}

#[test]
fn exported_problem_reads_back_equal() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = fixture("exp6b");
    let o = signorini(
        &["export", scene_path.to_str().unwrap(), "--out", "x"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = dir.path().join("x");

    let scene = run::load_scene(Some(&scene_path)).unwrap();
    let prepared = run::prepare(&scene, &MeshLimits::default()).unwrap();
    let qp = &prepared.qp;

    for (name, m) in [("A.mtx", &qp.stiffness), ("B.mtx", &qp.constraints)] {
        let read: sprs::TriMat<f64> = sprs::io::read_matrix_market(out.join(name)).unwrap();
        let read: sprs::CsMat<f64> = read.to_csc();
        assert_eq!(read.shape(), m.shape(), "{name}");
        assert_eq!(read.nnz(), m.nnz(), "{name}");
        for (v, (i, j)) in m.iter() {
            assert_eq!(read.get(i, j), Some(v), "{name} ({i},{j})");
        }
    }
    assert_eq!(read_dense(&out.join("f.mtx")), qp.load);
    assert_eq!(read_dense(&out.join("g.mtx")), qp.gap);
    let dofs = std::fs::read_to_string(out.join("dofs.csv")).unwrap();
    assert_eq!(dofs.lines().count(), qp.dofs() + 1);
    assert!(dofs.lines().nth(1).unwrap().contains(','));
    let rows = std::fs::read_to_string(out.join("rows.csv")).unwrap();
    assert_eq!(rows.lines().count(), qp.rows() + 1);
    // Without friction the export is what it was before blocks.csv existed (A, f, B, g and
    // dofs.csv are checked above): rows.csv keeps its ten columns, README.txt its problem line;
    // blocks.csv lists every row as non-negative, and the files read back as that problem.
    assert_eq!(
        rows.lines().next().unwrap(),
        "row,pair,slave,slave_node,x,y,masters,nx,ny,gap"
    );
    let readme = std::fs::read_to_string(out.join("README.txt")).unwrap();
    assert!(readme.contains("Problem: minimise 1/2 x'Ax - f'x subject to Bx <= g\n"));
    assert!(!readme.contains("box"), "{readme}");
    let blocks = std::fs::read_to_string(out.join("blocks.csv")).unwrap();
    let expected: String = std::iter::once("row,kind,bound".to_string())
        .chain((0..qp.rows()).map(|i| format!("{i},non-negative,")))
        .map(|l| l + "\n")
        .collect();
    assert_eq!(blocks, expected);
    let files = signorini::qp_files::read_qp_dir(&out).unwrap();
    assert_eq!(
        files.qp.blocks,
        vec![signorini_core::qp::ConstraintBlock::NonNegative { rows: qp.rows() }]
    );
    // 6b prescribes ux = −0.08 on the middle body: the lifted load is in f, not in extra rows.
    assert!(qp.load.iter().any(|f| *f != 0.0));
}

#[test]
fn compare_runs_every_backend_on_one_problem() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = fixture("exp2b");
    let o = signorini(
        &[
            "compare",
            scene_path.to_str().unwrap(),
            "--out",
            "c",
            "--tol",
            "1e-9",
        ],
        dir.path(),
    );
    let stdout = common::succeeded(&o);
    // The default backends: osqp only when compiled in.
    let defaults: &[&str] = if cfg!(feature = "osqp") {
        &["clarabel", "osqp", "dual-pgs", "dual-uzawa"]
    } else {
        &["clarabel", "dual-pgs", "dual-uzawa"]
    };
    for b in defaults {
        assert!(stdout.contains(b), "table lacks {b}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("c/compare.json")).unwrap())
            .unwrap();
    assert!(json["floor_s"].as_f64().unwrap() > 0.0);
    // The floor's factor: the project's ordering, and at least one nonzero of L per column of A
    // (its diagonal), at most the dense lower triangle.
    assert_eq!(json["floor_ordering"], "amd");
    let (nnz_l, dofs) = (
        json["floor_nnz_l"].as_u64().unwrap(),
        json["dofs"].as_u64().unwrap(),
    );
    assert!(nnz_l >= dofs && nnz_l <= dofs * (dofs + 1) / 2, "{nnz_l}");
    assert!(
        stdout.contains(&format!("amd ordering, nnz(L) {nnz_l}")),
        "{stdout}"
    );
    let rows = json["backends"].as_array().unwrap();
    assert_eq!(rows.len(), defaults.len());
    let scale = 0.4; // exp2b's largest displacement is about 0.39
    for r in rows {
        assert_eq!(r["status"], "solved", "{r}");
        assert!(r["ratio_to_floor"].as_f64().unwrap() > 0.0);
        assert!(r["max_du"].as_f64().unwrap() <= 1e-6 * scale, "{r}");
        assert_eq!(r["active"], rows[0]["active"]);
    }
    let csv = std::fs::read_to_string(dir.path().join("c/compare.csv")).unwrap();
    assert!(csv.starts_with("backend,status,iterations,solve_s,floor_s,ratio_to_floor"));
    assert_eq!(csv.lines().count(), 1 + defaults.len());
}

#[test]
fn compare_refuses_unknown_backends_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let o = signorini(
        &["compare", "--backends", "clarabel,cplex", "--out", "c"],
        dir.path(),
    );
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("cplex"));
    assert!(!dir.path().join("c").exists());
}

#[test]
fn compare_refuses_a_scene_without_contact_rows() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(fixture("exp2b")).unwrap();
    let cut = text.find("[[contact]]").unwrap();
    let end = text.find("[[probe]]").unwrap();
    std::fs::write(
        dir.path().join("free.toml"),
        format!("{}{}", &text[..cut], &text[end..]),
    )
    .unwrap();
    for cmd in [
        vec!["compare", "free.toml"],
        vec!["sweep", "free.toml", "--hmax", "0.3"],
    ] {
        let mut args = cmd.clone();
        args.extend(["--out", "c"]);
        let o = signorini(&args, dir.path());
        assert!(!o.status.success(), "{cmd:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("no contact constraint row"), "{err}");
        assert!(!dir.path().join("c/compare.json").exists());
        assert!(!dir.path().join("c/sweep.csv").exists());
    }
}

/// A backend that cannot run on the problem (the condensed dual form on a body held by contact
/// alone) is a row with status "error" and its reason; the other backends still run, and the
/// exit code says "not solved" (2).  Before, the whole comparison stopped at that backend.
#[test]
fn a_backend_that_cannot_run_is_an_error_row() {
    let dir = tempfile::tempdir().unwrap();
    let scene = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/hard/floating.toml");
    let o = signorini(
        &[
            "compare",
            scene.to_str().unwrap(),
            "--backends",
            "clarabel/dual,pdas",
            "--out",
            "c",
        ],
        dir.path(),
    );
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("c/compare.json")).unwrap())
            .unwrap();
    let rows = json["backends"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    assert_eq!(rows[0]["backend"], "clarabel/dual");
    assert_eq!(rows[0]["status"], "error");
    assert!(rows[0]["message"].as_str().unwrap().contains("rigid-body"));
    assert_eq!(rows[1]["backend"], "pdas");
    assert_eq!(rows[1]["status"], "solved");
    assert!(String::from_utf8_lossy(&o.stdout).contains("error: backend `clarabel/dual`"));
}

/// Friction along a load path has no single QP (each increment measures the slip from the
/// previous answer): `export` refuses it with the reason (exit 1) and writes nothing, rather
/// than a problem the scene does not solve.
#[test]
fn friction_along_a_load_path_is_not_exported() {
    let dir = tempfile::tempdir().unwrap();
    let scene =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/accuracy/cattaneo.toml");
    let o = signorini(
        &["export", scene.to_str().unwrap(), "--out", "x"],
        dir.path(),
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("friction along a load path"), "{err}");
    assert!(!dir.path().join("x/README.txt").exists());
}
