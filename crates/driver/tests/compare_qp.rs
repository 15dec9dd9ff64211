//! `signorini compare --qp DIR`: a QP read from Matrix Market files through every backend.
//!
//! * an exported scene's QP gives what `compare SCENE` gives;
//! * the spring chain written by `scripts/qp-from-scipy.py` (fixtures/qp/spring-chain) gives its
//!   hand-known optimum from every backend;
//! * malformed input is refused naming the file and the line, exit code 1, nothing written;
//! * a QP with a singular A is solved by every backend when `N.mtx` (written by `export`) gives
//!   its null space, and is an error row for the dual backends without it; a wrong N.mtx is
//!   refused;
//! * a frictional scene's export (Tresca, or Coulomb's Tresca snapshot) compares to the scene's
//!   own objective and forces: `blocks.csv` carries the box rows; a bad `blocks.csv` line is
//!   refused naming the file and the line.

mod common;
use common::signorini;

use std::path::{Path, PathBuf};

use signorini::qp_files::read_qp_dir;

fn repo(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("read the report"))
        .expect("the report is JSON")
}

/// Every backend name this build accepts (the primal and dual forms, the chain).
fn every_backend() -> Vec<&'static str> {
    let mut names = vec![
        "clarabel",
        "dual-pgs",
        "dual-uzawa",
        "dual-ssn",
        "pdas",
        "clarabel/dual",
        "auto",
    ];
    if cfg!(feature = "osqp") {
        names.extend(["osqp", "osqp/dual"]);
    }
    names
}

/// `compare SCENE` and `compare --qp` on the scene's export: the same problem, so the same size,
/// the same floor factor (the reader keeps A's stored pattern, explicit zeros included), and per
/// backend the same status, active set and objective.
#[test]
fn an_exported_scene_compares_as_the_scene_does() {
    let dir = tempfile::tempdir().unwrap();
    let backends = if cfg!(feature = "osqp") {
        "clarabel,osqp,dual-pgs,dual-uzawa,pdas"
    } else {
        "clarabel,dual-pgs,dual-uzawa,pdas"
    };
    // 2b: traction; 6b: a prescribed displacement, whose lifted load is all f carries.
    for name in ["exp2b", "exp6b"] {
        let scene = repo(&format!("fixtures/seed/{name}.toml"));
        let scene = scene.to_str().unwrap();
        let o = signorini(&["export", scene, "--out", "x"], dir.path());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let common = ["--backends", backends, "--tol", "1e-9"];
        let mut args = vec!["compare", scene, "--out", "s"];
        args.extend(common);
        let o = signorini(&args, dir.path());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let mut args = vec!["compare", "--qp", "x", "--out", "q"];
        args.extend(common);
        let o = signorini(&args, dir.path());
        let stdout = common::succeeded(&o);
        assert!(
            stdout.starts_with("QP from x (exported from \"Experiment"),
            "{stdout}"
        );
        let (s, q) = (
            json(&dir.path().join("s/compare.json")),
            json(&dir.path().join("q/compare.json")),
        );
        for key in ["dofs", "constraints", "floor_nnz_l", "floor_ordering"] {
            assert_eq!(s[key], q[key], "{name} {key}");
        }
        // Where the QP came from, and no mesh to time.
        assert_eq!(q["source"], "x");
        assert!(q.get("mesh_s").is_none() && q.get("assemble_s").is_none());
        assert!(q["read_s"].as_f64().unwrap() > 0.0);
        assert!(s.get("source").is_none() && s["mesh_s"].as_f64().is_some());
        let (s, q) = (
            s["backends"].as_array().unwrap(),
            q["backends"].as_array().unwrap(),
        );
        assert_eq!(s.len(), q.len());
        for (a, b) in s.iter().zip(q) {
            assert_eq!(a["backend"], b["backend"]);
            assert_eq!(a["status"], "solved", "{a}");
            assert_eq!(b["status"], "solved", "{b}");
            assert_eq!(a["active"], b["active"], "{name} {}", a["backend"]);
            let (oa, ob) = (
                a["objective"].as_f64().unwrap(),
                b["objective"].as_f64().unwrap(),
            );
            // Both answers meet the relative KKT tolerance 1e-9 on the same QP; the objective is
            // stationary at the optimum, so each is within O(1e-9)·|objective| of it: 1e-7 is a
            // hundredfold margin.
            assert!(
                (oa - ob).abs() <= 1e-7 * oa.abs(),
                "{name} {}: {oa} vs {ob}",
                a["backend"]
            );
        }
    }
}

/// The fixture reads back as exactly the QP of `signorini_core::examples::spring_chain`, built
/// independently in Rust.
#[test]
fn the_scipy_fixture_is_the_spring_chain() {
    let files = read_qp_dir(&repo("fixtures/qp/spring-chain")).unwrap();
    let known = signorini_core::examples::spring_chain().problem;
    assert_eq!(files.qp.load, known.load);
    assert_eq!(files.qp.gap, known.gap);
    assert_eq!(files.qp.stiffness.to_dense(), known.stiffness.to_dense());
    assert_eq!(
        files.qp.constraints.to_dense(),
        known.constraints.to_dense()
    );
    assert!(files.qp.kernel.is_empty());
    assert!(!files.general, "A.mtx is written `symmetric`");
}

/// 10 unit springs, the last node pushed by f = 1 against a wall at 5: x_i = (i + 1)/2, λ = ½.
/// Then Ax = f − Bᵀλ = ½ e₁₀, so ½xᵀAx = ½ · x₁₀ · ½ = 1.25 and fᵀx = x₁₀ = 5: the objective is
/// −3.75, and the one row is active.  Every backend must find it.
#[test]
fn every_backend_finds_the_known_optimum_of_the_scipy_fixture() {
    let dir = tempfile::tempdir().unwrap();
    let fixture = repo("fixtures/qp/spring-chain");
    let names = every_backend().join(",");
    let o = signorini(
        &[
            "compare",
            "--qp",
            fixture.to_str().unwrap(),
            "--backends",
            &names,
            "--out",
            "c",
        ],
        dir.path(),
    );
    let stdout = common::succeeded(&o);
    assert!(
        stdout.contains("10 unknowns, 1 constraint rows"),
        "{stdout}"
    );
    let report = json(&dir.path().join("c/compare.json"));
    let rows = report["backends"].as_array().unwrap();
    assert_eq!(rows.len(), every_backend().len());
    for r in rows {
        assert_eq!(r["status"], "solved", "{r}");
        assert_eq!(r["active"], 1, "{r}");
        let objective = r["objective"].as_f64().unwrap();
        // Solved means KKT residuals ≤ 1e-9 relative; the objective's error is of that order
        // times its scale (3.75): 1e-7 leaves a margin of ~25.
        assert!((objective + 3.75).abs() < 1e-7, "{r}");
        // x agrees with the reference backend's to the tolerance's order (x is O(5)).
        assert!(r["max_du"].as_f64().unwrap() < 1e-6, "{r}");
    }
    let csv = std::fs::read_to_string(dir.path().join("c/compare.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + rows.len());
}

/// A QP directory with one file replaced by `text`.
fn broken(dir: &Path, file: &str, text: &str) -> PathBuf {
    let qp = dir.join("qp");
    let _ = std::fs::remove_dir_all(&qp);
    std::fs::create_dir(&qp).expect("make the QP directory");
    for name in ["A.mtx", "f.mtx", "B.mtx", "g.mtx"] {
        std::fs::copy(repo("fixtures/qp/spring-chain").join(name), qp.join(name))
            .expect("copy the fixture");
    }
    std::fs::write(qp.join(file), text).expect("write the broken file");
    qp
}

/// The fixture's A with `line` (4-based: line 4 is the first entry) replaced.
fn a_with(line: usize, replacement: &str) -> String {
    let text =
        std::fs::read_to_string(repo("fixtures/qp/spring-chain/A.mtx")).expect("read the fixture");
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    lines[line - 1] = replacement.to_string();
    lines.join("\n") + "\n"
}

const ARRAY: &str = "%%MatrixMarket matrix array real general\n";
const COORD: &str = "%%MatrixMarket matrix coordinate real general\n";

/// Every malformed case: exit code 1, the file and line named (`file:line:` as compilers do),
/// the reason given, and nothing written (the output directory is not even created).
#[test]
fn malformed_input_is_refused_with_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let ones = |n: usize| "1\n".repeat(n);
    let cases: Vec<(&str, String, &str)> = vec![
        // Shapes.  The fixture has n = 10, m = 1; each size line is line 2 here, 3 in the fixture.
        (
            "A.mtx",
            format!("{COORD}10 9 1\n1 1 2\n"),
            "A.mtx:2: A must be square (n×n), not 10×9",
        ),
        (
            "f.mtx",
            format!("{ARRAY}9 1\n{}", ones(9)),
            "f.mtx:2: f has length 9 but A",
        ),
        (
            "f.mtx",
            format!("{ARRAY}10 2\n{}", ones(20)),
            "f.mtx:2: f must be a vector (n×1 or 1×n), not 10×2",
        ),
        (
            "B.mtx",
            format!("{COORD}1 9 1\n1 9 1\n"),
            "B.mtx:2: B is 1×9 but must have n = 10 columns",
        ),
        (
            "g.mtx",
            format!("{ARRAY}2 1\n5\n5\n"),
            "g.mtx:2: g has length 2 but B",
        ),
        // Sizes the entries cannot fill (refused before allocating them).
        (
            "A.mtx",
            format!("{COORD}1000000000000 1000000000000 1\n1 1 2\n"),
            "A.mtx:2: A declares 1000000000000 unknowns but stores 1 entries",
        ),
        (
            "B.mtx",
            format!("{COORD}1000000000000 10 1\n1 10 1\n"),
            "B.mtx:2: B declares 1000000000000 rows but stores 1 entries",
        ),
        // Symmetry: a `general` A whose (1, 2) entry differs from (2, 1).
        (
            "A.mtx",
            format!("{COORD}2 2 3\n1 1 2\n2 1 -1\n1 2 -1.5\n"),
            "A.mtx:4: A is not symmetric: A(2, 1) = -1e0 here but A(1, 2) = -1.5e0 (line 5)",
        ),
        // An upper-triangle entry in a `symmetric` file.
        (
            "A.mtx",
            a_with(5, "1 2 -1"),
            "A.mtx:5: entry (1, 2) lies above the diagonal",
        ),
        // Values.
        (
            "A.mtx",
            a_with(6, "2 2 NaN"),
            "A.mtx:6: value `NaN` is not finite",
        ),
        (
            "g.mtx",
            format!("{ARRAY}1 1\ninf\n"),
            "g.mtx:3: value `inf` is not finite",
        ),
        (
            "f.mtx",
            format!("{ARRAY}10 1\n{}x1\n", ones(9)),
            "f.mtx:12: `x1` is not a number",
        ),
        (
            "B.mtx",
            format!("{COORD}1 10 1\n1 10 one\n"),
            "B.mtx:3: `one` is not a number",
        ),
        // Indices.
        (
            "A.mtx",
            a_with(7, "11 2 -1"),
            "A.mtx:7: row index 11 out of range 1..=10",
        ),
        (
            "B.mtx",
            format!("{COORD}1 10 1\n1 0 1\n"),
            "B.mtx:3: column index 0 out of range 1..=10",
        ),
        // Counts.
        (
            "B.mtx",
            format!("{COORD}1 10 1\n1 10 1\n1 9 1\n"),
            "B.mtx:4: more entries than the 1 declared on line 2",
        ),
        (
            "B.mtx",
            format!("{COORD}1 10 2\n1 10 1\n"),
            "B.mtx: the file ends after 1 of the 2 entries declared on line 2",
        ),
        (
            "f.mtx",
            format!("{ARRAY}10 1\n1 2\n"),
            "f.mtx:3: expected one value per line",
        ),
        // Headers and size lines.
        (
            "A.mtx",
            "10 10 19\n".to_string(),
            "A.mtx:1: not a Matrix Market header",
        ),
        (
            "B.mtx",
            "%%MatrixMarket matrix coordinate complex general\n1 10 1\n1 10 1 0\n".to_string(),
            "B.mtx:1: field `complex` not supported",
        ),
        (
            "A.mtx",
            "%%MatrixMarket matrix coordinate real skew-symmetric\n".to_string(),
            "A.mtx:1: symmetry `skew-symmetric` not supported",
        ),
        (
            "g.mtx",
            format!("{ARRAY}1\n5\n"),
            "g.mtx:2: size line `1` must be `rows cols`: two non-negative integers",
        ),
        // Positive semidefiniteness, as far as one entry tells.
        (
            "A.mtx",
            a_with(4, "1 1 -2"),
            "A.mtx:4: diagonal entry A(1, 1) = -2e0 is negative",
        ),
        // The constraint blocks (the fixture's B has one row, row 0).
        (
            "blocks.csv",
            "row,kind\n0,box,1\n".to_string(),
            "blocks.csv:1: the header must be `row,kind,bound`",
        ),
        (
            "blocks.csv",
            "row,kind,bound\n0,cone,\n".to_string(),
            "blocks.csv:2: unknown kind `cone` (non-negative or box)",
        ),
        (
            "blocks.csv",
            "row,kind,bound\n0,box,-1\n".to_string(),
            "blocks.csv:2: bound -1e0 is negative",
        ),
        (
            "blocks.csv",
            "row,kind,bound\n0,box,NaN\n".to_string(),
            "blocks.csv:2: bound `NaN` is not finite",
        ),
        (
            "blocks.csv",
            "row,kind,bound\n0,box,\n".to_string(),
            "blocks.csv:2: a box row needs its bound",
        ),
        (
            "blocks.csv",
            "row,kind,bound\n0,box,one\n".to_string(),
            "blocks.csv:2: bound `one` is not a number",
        ),
        (
            "blocks.csv",
            "row,kind,bound\n0,non-negative,0.5\n".to_string(),
            "blocks.csv:2: a non-negative row takes no bound",
        ),
        (
            "blocks.csv",
            "row,kind,bound\n0,box\n".to_string(),
            "blocks.csv:2: expected three fields `row,kind,bound`",
        ),
        (
            "blocks.csv",
            "row,kind,bound\n\n0,box,1\n1,box,1\n".to_string(),
            "blocks.csv:4: row 1 is beyond B's 1 rows",
        ),
        (
            "blocks.csv",
            "row,kind,bound\n1,box,1\n".to_string(),
            "blocks.csv:2: row 1 is beyond B's 1 rows",
        ),
        (
            "blocks.csv",
            "row,kind,bound\n".to_string(),
            "blocks.csv: lists 0 rows but B has 1",
        ),
    ];
    for (file, text, expected) in &cases {
        let qp = broken(dir.path(), file, text);
        let o = signorini(
            &["compare", "--qp", qp.to_str().unwrap(), "--out", "c"],
            dir.path(),
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{file}: {err}");
        let named = format!("{}", qp.join(expected).display());
        assert!(err.contains(&named), "expected `{named}` in:\n{err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(!dir.path().join("c").exists(), "{file}: {expected}");
    }
    // A missing file, and a directory that is not there at all.
    let qp = broken(dir.path(), "g.mtx", "");
    std::fs::remove_file(qp.join("g.mtx")).unwrap();
    for (arg, expected) in [
        (
            qp.clone(),
            format!("{}: missing", qp.join("g.mtx").display()),
        ),
        (
            dir.path().join("nowhere"),
            format!("{}: not a directory", dir.path().join("nowhere").display()),
        ),
    ] {
        let o = signorini(
            &["compare", "--qp", arg.to_str().unwrap(), "--out", "c"],
            dir.path(),
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert!(err.contains(&expected), "expected `{expected}` in:\n{err}");
        assert!(!dir.path().join("c").exists());
    }
}

/// A QP without constraint rows is one linear solve: nothing to compare, as for a scene without
/// contact (exit 1, nothing written).
#[test]
fn a_qp_without_rows_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let qp = broken(dir.path(), "B.mtx", &format!("{COORD}0 10 0\n"));
    std::fs::write(qp.join("g.mtx"), format!("{ARRAY}0 1\n")).unwrap();
    let o = signorini(
        &["compare", "--qp", qp.to_str().unwrap(), "--out", "c"],
        dir.path(),
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("B has no row"), "{err}");
    assert!(!dir.path().join("c").exists());
}

/// `--qp` replaces the scene: both at once is a usage error.
#[test]
fn qp_and_a_scene_together_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo("fixtures/seed/exp2b.toml");
    let fixture = repo("fixtures/qp/spring-chain");
    let o = signorini(
        &[
            "compare",
            scene.to_str().unwrap(),
            "--qp",
            fixture.to_str().unwrap(),
            "--out",
            "c",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("cannot be used with"));
    assert!(!dir.path().join("c").exists());
}

/// A floating body's QP: A is singular.  `export` writes its null space as N.mtx, with which
/// every backend — the dual ones included — solves it, to the objective of `compare` on the
/// scene itself.  Without N.mtx, the primal backends solve it and the dual ones (which need A⁻¹
/// or the rigid-body modes) are error rows saying so; the comparison still finishes (exit 2),
/// it does not crash.  A wrong N.mtx is refused naming the file.
#[test]
fn a_singular_a_needs_its_null_space_for_the_dual_backends() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo("fixtures/hard/floating.toml");
    let o = signorini(
        &["export", scene.to_str().unwrap(), "--out", "x"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.path().join("x/N.mtx").exists());
    // (clarabel/dual is left out: the condensed dual needs A⁻¹ and refuses a floating body
    // whatever the files carry.)
    let backends = "clarabel,pdas,dual-pgs,dual-ssn";
    let compare = |args: &[&str]| {
        let mut all = vec!["compare", "--backends", backends];
        all.extend_from_slice(args);
        signorini(&all, dir.path())
    };
    let o = compare(&["--qp", "x", "--out", "c"]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let o = compare(&[scene.to_str().unwrap(), "--out", "s"]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let files = json(&dir.path().join("c/compare.json"));
    let direct = json(&dir.path().join("s/compare.json"));
    let reference = direct["backends"][0]["objective"].as_f64().unwrap();
    for r in files["backends"].as_array().unwrap() {
        assert_eq!(r["status"], "solved", "{r}");
        // Both solved to tol 1e-9: the objectives agree far better than 1e-6.
        let o = r["objective"].as_f64().unwrap();
        assert!((o - reference).abs() <= 1e-6 * reference.abs(), "{r}");
    }

    // Without the null space: error rows for the dual backends.
    std::fs::remove_file(dir.path().join("x/N.mtx")).unwrap();
    let o = compare(&["--qp", "x", "--out", "c2"]);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let report = json(&dir.path().join("c2/compare.json"));
    let rows = report["backends"].as_array().unwrap();
    for r in &rows[..2] {
        assert_eq!(r["status"], "solved", "{r}");
    }
    for r in &rows[2..] {
        assert_eq!(r["status"], "error", "{r}");
        assert!(r["objective"].is_null(), "{r}");
        let message = r["message"].as_str().unwrap();
        assert!(
            message.contains("A is singular and the QP files carry no null space (N.mtx)"),
            "{message}"
        );
    }

    // A vector that is not in A's null space (a unit vector: A's column, O(1)), or of the
    // wrong length, is refused naming N.mtx.
    let n = report["dofs"].as_u64().unwrap() as usize;
    let mut text = format!("%%MatrixMarket matrix array real general\n{n} 1\n1\n");
    text.push_str(&"0\n".repeat(n - 1));
    std::fs::write(dir.path().join("x/N.mtx"), &text).unwrap();
    let o = compare(&["--qp", "x", "--out", "c3"]);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("N.mtx") && err.contains("not in A's null space"),
        "{err}"
    );
    std::fs::write(
        dir.path().join("x/N.mtx"),
        "%%MatrixMarket matrix array real general\n2 1\n1\n0\n",
    )
    .unwrap();
    let o = compare(&["--qp", "x", "--out", "c3"]);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("N must be n×k"), "{err}");
    assert!(!dir.path().join("c3").exists());
}

/// The answer of `signorini solve SCENE` in `out`: its objective and, per contact row in B's
/// order (pair by pair, node by node), the normal and tangential multipliers of result.json.
fn solved(dir: &Path, scene: &Path, out: &str) -> (f64, Vec<f64>, Vec<f64>) {
    let o = signorini(
        &["solve", scene.to_str().expect("a UTF-8 path"), "--out", out],
        dir,
    );
    common::succeeded(&o);
    let result = json(&dir.join(out).join("result.json"));
    assert_eq!(result["status"], "solved", "{}", scene.display());
    let nodes: Vec<&serde_json::Value> = result["contacts"]
        .as_array()
        .expect("contacts")
        .iter()
        .flat_map(|c| c["nodes"].as_array().expect("nodes"))
        .collect();
    let normal = nodes
        .iter()
        .map(|n| n["multiplier"].as_f64().expect("a multiplier"))
        .collect();
    let tangential = nodes
        .iter()
        .map(|n| {
            n["tangential_multiplier"]
                .as_f64()
                .expect("a tangential multiplier")
        })
        .collect();
    (
        result["objective"].as_f64().expect("the objective"),
        normal,
        tangential,
    )
}

/// Issue 41, item 5: the exported problem of a frictional scene is the problem the scene solves.
/// Before, every row of B was written as `Bx ≤ g` (the tangential box rows as one-sided rows)
/// and `compare --qp` answered `solved` for another problem (tresca-nts: objective −9.6357e-4
/// where the scene's is −9.6157e-4; a tangential force must then be ≥ 0, while the dragged block's
/// are all negative).  Now `blocks.csv` carries each row's kind and bound: `compare --qp` finds
/// the scene's own objective, and a backend run on the files finds the scene's own normal and
/// tangential forces.  A Coulomb scene is a Tresca snapshot at the bounds μ max(0, λₙ) of its
/// answer, whose solution is that answer (friction-stick: every node sticks, its tangential
/// forces interior to the bounds and fixed by equilibrium; friction-slide: every node slips).
#[test]
fn a_frictional_export_is_the_problem_the_scene_solves() {
    let dir = tempfile::tempdir().unwrap();
    for (scene, coulomb) in [
        ("fixtures/qpset/tresca-nts.toml", false),
        ("fixtures/hard/friction-stick.toml", true),
        ("fixtures/hard/friction-slide.toml", true),
    ] {
        let path = repo(scene);
        let (objective, normal, tangential) = solved(dir.path(), &path, "s");
        let o = signorini(
            &["export", path.to_str().unwrap(), "--out", "x"],
            dir.path(),
        );
        common::succeeded(&o);
        let err = String::from_utf8_lossy(&o.stderr);
        let readme = std::fs::read_to_string(dir.path().join("x/README.txt")).unwrap();
        assert!(readme.contains("s_i |(Bx - g)_i|"), "{scene}: {readme}");
        // A Coulomb export says, in README.txt and on stderr, that it is a Tresca snapshot.
        for said in [readme.as_str(), &err] {
            assert_eq!(
                said.contains("Coulomb friction is not a QP") && said.contains("Tresca snapshot"),
                coulomb,
                "{scene}: {said}"
            );
        }
        // rows.csv lists every row of B: the normal rows, then one tangential row per node.
        let rows = std::fs::read_to_string(dir.path().join("x/rows.csv")).unwrap();
        let m = normal.len() + tangential.len();
        assert_eq!(rows.lines().count(), 1 + m, "{scene}");
        assert_eq!(
            rows.lines().filter(|l| l.contains(",tangential,")).count(),
            tangential.len(),
            "{scene}"
        );

        // Every backend that solves box rows finds the scene's objective.  Each answer meets the
        // relative KKT tolerance 1e-9 (the default of `solve` and `compare`) on the same problem,
        // so each objective is within O(1e-9)·|objective| of the optimum (a Coulomb snapshot's
        // bounds μ λₙ carry the answer's own 1e-9 error, which moves the optimum by as much):
        // 1e-6 leaves a thousandfold margin, and the defect's 2e-3 lies far outside it.
        let o = signorini(
            &[
                "compare",
                "--qp",
                "x",
                "--backends",
                "clarabel,pdas",
                "--out",
                "q",
            ],
            dir.path(),
        );
        common::succeeded(&o);
        let report = json(&dir.path().join("q/compare.json"));
        assert_eq!(report["constraints"].as_u64().unwrap() as usize, m);
        for r in report["backends"].as_array().unwrap() {
            assert_eq!(r["status"], "solved", "{scene}: {r}");
            let o = r["objective"].as_f64().unwrap();
            assert!(
                (o - objective).abs() <= 1e-6 * objective.abs(),
                "{scene} {}: {o} vs the scene's {objective}",
                r["backend"]
            );
        }

        // The forces: a backend on the files' problem, against result.json.  Both answers meet
        // the KKT tolerance 1e-9, but multipliers are not stationary as the objective is: their
        // error is that residual times the conditioning of B A⁻¹ Bᵀ (these multipliers are
        // unique: B has full row rank).  Measured: 5.6e-8 (tresca-nts), 7.7e-10 (friction-stick)
        // and 1.3e-7 (friction-slide) of the largest force; 1e-5 is 80 times the worst, and five
        // orders below the defect's O(1) error (a force of the wrong sign or at another bound).
        let files = read_qp_dir(&dir.path().join("x")).unwrap();
        let mut backend =
            signorini::backends::make_backend(signorini::backends::BackendKind::Clarabel).unwrap();
        let answer = backend
            .solve(&files.qp, &signorini_core::qp::SolveOptions::default())
            .unwrap();
        assert_eq!(
            answer.status,
            signorini_core::qp::QpStatus::Solved,
            "{scene}"
        );
        let expected: Vec<f64> = normal.iter().chain(&tangential).copied().collect();
        let largest = expected.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
        for (i, (got, want)) in answer.multipliers.iter().zip(&expected).enumerate() {
            assert!(
                (got - want).abs() <= 1e-5 * largest,
                "{scene}: row {i}: {got:e} from the files, {want:e} from the scene"
            );
        }
    }
}
