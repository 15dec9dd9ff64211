//! `signorini compare --fclib FILE`: FCLIB global problems read back and solved by our backends.
//! Files written by an independent writer (Python's h5py, installed by .ci/run) in FCLIB's
//! other storages (triplets, compressed rows) with an answer known in closed form, and our own
//! exports read back (export → import → the same problem and answer).
#![allow(clippy::unwrap_used)]

mod common;
use common::{json, signorini};

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fixtures/hard/{name}"))
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn python(script: &str, args: &[&str]) {
    let o = Command::new("python3")
        .arg("-c")
        .arg(script)
        .args(args)
        .output()
        .expect("python3 (with h5py: pip install h5py, as .ci/run does)");
    assert!(o.status.success(), "the writer failed:\n{}", text(&o));
}

/// Four points on a rigid plane, each with its own 2×2 block of M = k I (k = 2), written by h5py:
/// M as triplets (nz ≥ 0), H as compressed rows (nz = −2).  Point α has the normal entry
/// u_N = y_α + w_N and the tangential u_T = x_α, load f = (fx, −fy):
///
/// | α | μ   | fx  | fy | w_N | answer |
/// |---|-----|-----|----|-----|--------|
/// | 0 | 0.3 | 1.0 | 2  | 0   | slides: r = (2, −0.6), x = (1 − 0.6)/2 = 0.2, y = 0 |
/// | 1 | 0.3 | 0.3 | 2  | 0   | sticks: r = (2, −0.3), x = 0, y = 0 |
/// | 2 | 0   | 1.0 | 2  | 0   | frictionless: r = (2, 0), x = 0.5, y = 0 |
/// | 3 | 0.3 | 0.4 | 1  | 1   | open (the gap 1 exceeds fy/k): r = 0, x = 0.2, y = −0.5 |
///
/// (M v = H r + f: k x = r_T + fx, k y = r_N − fy; sliding r_T = −μ r_N sign u_T.)
const ANALYTIC: &str = r#"
import sys
import h5py, numpy as np
k, mu = 2.0, [0.3, 0.3, 0.0, 0.3]
fx, fy, wn = [1.0, 0.3, 1.0, 0.4], [2.0, 2.0, 2.0, 1.0], [0.0, 0.0, 0.0, 1.0]
n, nc = 8, 4
f = np.zeros(n); w = np.zeros(2 * nc)
for a in range(nc):
    f[2 * a], f[2 * a + 1] = fx[a], -fy[a]
    w[2 * a] = wn[a]
# H: row 2a (x_a) has column 2a+1 (tangent), row 2a+1 (y_a) column 2a (normal): CSR.
hp = np.arange(n + 1, dtype=np.int32)
hi = np.array([2 * (r // 2) + (1 - r % 2) for r in range(n)], dtype=np.int32)
hx = np.ones(n)
v = np.array([0.2, 0, 0, 0, 0.5, 0, 0.2, -0.5])
r = np.array([2, -0.6, 2, -0.3, 2, 0, 0, 0])
u = np.zeros(2 * nc)
for a in range(nc):
    u[2 * a], u[2 * a + 1] = v[2 * a + 1] + w[2 * a], v[2 * a]
out = h5py.File(sys.argv[1], "w")
g = out.create_group("fclib_global")
g["spacedim"] = np.array([int(sys.argv[2])], dtype=np.int32)
def mat(name, m, ncol, nz, p, i, x):
    grp = g.create_group(name)
    for key, val in [("nzmax", len(x)), ("m", m), ("n", ncol), ("nz", nz)]:
        grp[key] = np.array([val], dtype=np.int32)
    grp["p"], grp["i"], grp["x"] = p, i, x
diag = np.arange(n, dtype=np.int32)
mat("M", n, n, n, diag, diag, np.full(n, k))
mat("H", n, 2 * nc, -2, hp, hi, hx)
vec = g.create_group("vectors")
vec["f"], vec["w"], vec["mu"] = f, w, np.array(mu)
g.create_group("info")["title"] = np.bytes_("four points on a plane")
s = out.create_group("solution")
s["v"], s["u"], s["r"] = v, u, r
out.close()
"#;

fn compare_fclib(dir: &Path, file: &Path, backends: &str) -> (Output, PathBuf) {
    let out = dir.join(format!("cmp-{backends}"));
    let o = signorini(
        &[
            "compare",
            "--fclib",
            file.to_str().unwrap(),
            "--backends",
            backends,
            "--out",
            out.to_str().unwrap(),
        ],
        dir,
    );
    (o, out.join("compare.json"))
}

fn row<'a>(report: &'a Value, backend: &str) -> &'a Value {
    report["backends"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["backend"] == backend)
        .unwrap_or_else(|| panic!("no row {backend}: {report}"))
}

/// The closed-form answer of [`ANALYTIC`] (slide, stick, frictionless and open contacts at
/// once), from a file in storages our writer never uses.  dual-ssn and pdas end on the exact
/// active set, where the answer is one linear solve of M = 2I: round-off only (≤ 1e-12
/// relative).  (pdas and osqp were `inaccurate` here: the points pressed onto the plane do not
/// move, and their round-off penetration was judged against that motion alone — fixed by
/// `signorini_qp::BODY_MOTION_FLOOR`.)  clarabel
/// stops at tol 1e-9 on the relative complementarity λ·gap: with M = 2I (condition 1) a row
/// may split that product as √1e-9 ≈ 3.2e-5 on each side, so 1e-4 bounds its distance.
#[test]
fn a_hand_written_2d_problem_solves_to_its_closed_form_answer() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("points.hdf5");
    python(ANALYTIC, &[file.to_str().unwrap(), "2"]);
    let (o, report) = compare_fclib(dir.path(), &file, "dual-ssn,pdas,clarabel");
    assert!(o.status.success(), "{}", text(&o));
    let report = json(&report);
    assert_eq!(report["dofs"], 8);
    // 4 normal rows and the tangential rows of the 3 contacts with μ > 0.
    assert_eq!(report["constraints"], 7);
    assert!(
        report["scene"]
            .as_str()
            .unwrap()
            .contains("four points on a plane"),
        "{}",
        report["scene"]
    );
    for (backend, bound) in [("dual-ssn", 1e-12), ("pdas", 1e-12), ("clarabel", 1e-4)] {
        let r = row(&report, backend);
        assert_eq!(r["status"], "solved", "{r}");
        for key in ["v", "r"] {
            let d = r["stored"][key].as_f64().unwrap();
            assert!(d <= bound, "{backend}: stored {key} differs by {d:e}");
        }
    }
}

/// What our QP cannot state is refused with the reason, exit 1: a 3-D problem (spacedim 3),
/// a local one (W, q), and a file that is not HDF5.
#[test]
fn problems_our_qp_cannot_state_are_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let three = dir.path().join("three.hdf5");
    python(ANALYTIC, &[three.to_str().unwrap(), "3"]);
    let local = dir.path().join("local.hdf5");
    python(
        "import sys, h5py, numpy as np\nf = h5py.File(sys.argv[1], 'w')\nf.create_group('fclib_local')['spacedim'] = np.array([2], dtype=np.int32)\n",
        &[local.to_str().unwrap()],
    );
    let junk = dir.path().join("junk.hdf5");
    std::fs::write(&junk, "not hdf5").unwrap();
    for (file, word) in [
        (&three, "spacedim = 3"),
        (&local, "local problem"),
        (&junk, "junk.hdf5"),
    ] {
        let (o, _) = compare_fclib(dir.path(), file, "pdas");
        assert_eq!(o.status.code(), Some(1), "{}", text(&o));
        assert!(text(&o).contains(word), "{word}: {}", text(&o));
    }
    // HDF5's own words once: the error's chain prints its source after the context, so the
    // context must not repeat it (it did, "…signature not found: …signature not found").
    let (o, _) = compare_fclib(dir.path(), &junk, "pdas");
    assert_eq!(
        text(&o).matches("file signature not found").count(),
        1,
        "{}",
        text(&o)
    );
}

/// Export → import: `compare --fclib` of our own export of a Coulomb scene runs the scene's QP
/// itself — pdas, deterministic, gives the same iterations and objective as `compare SCENE`
/// (the same numbers in the same order: round-off of the sums only, 1e-12) — and its answer
/// agrees with the stored one (the default backend's at tol 1e-9) to 1e-6 relative: both meet
/// the relative residuals 1e-9, and M's condition number here (κ ∝ (L/h)², L/h = 5–20 with
/// linear triangles) is at most ~1e3.  A wrong map (a sign of H, the interleaving, a lost μ)
/// changes the problem: O(1) differences.
#[test]
fn our_own_export_reads_back_as_the_same_problem_and_answer() {
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "friction-slide.toml",
        "friction-stick.toml",
        "gap-closes.toml",
    ] {
        let scene = fixture(name);
        let file = dir.path().join(name.replace(".toml", ".hdf5"));
        let o = signorini(
            &[
                "export",
                scene.to_str().unwrap(),
                "--fclib",
                file.to_str().unwrap(),
            ],
            dir.path(),
        );
        assert!(o.status.success(), "{name}: {}", text(&o));
        let (o, imported) = compare_fclib(dir.path(), &file, "pdas");
        assert!(o.status.success(), "{name}: {}", text(&o));
        let out = dir.path().join(format!("scene-{name}"));
        let o = signorini(
            &[
                "compare",
                scene.to_str().unwrap(),
                "--backends",
                "pdas",
                "--out",
                out.to_str().unwrap(),
            ],
            dir.path(),
        );
        assert!(o.status.success(), "{name}: {}", text(&o));
        let (imported, direct) = (json(&imported), json(&out.join("compare.json")));
        assert_eq!(imported["dofs"], direct["dofs"], "{name}");
        assert_eq!(imported["constraints"], direct["constraints"], "{name}");
        let (a, b) = (row(&imported, "pdas"), row(&direct, "pdas"));
        assert_eq!(a["iterations"], b["iterations"], "{name}");
        let (oa, ob) = (
            a["objective"].as_f64().unwrap(),
            b["objective"].as_f64().unwrap(),
        );
        assert!(
            (oa - ob).abs() <= 1e-12 * ob.abs(),
            "{name}: objective {oa:e} imported, {ob:e} from the scene"
        );
        for key in ["v", "r"] {
            let d = a["stored"][key].as_f64().unwrap();
            assert!(d <= 1e-6, "{name}: stored {key} differs by {d:e}");
        }
    }
}
