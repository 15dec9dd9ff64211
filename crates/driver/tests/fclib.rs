//! `signorini export --fclib`: the FCLIB file read back by an independent reader (Python's h5py,
//! installed by .ci/run: Rust has no HDF5 reader that is not the library we write with), and
//! checked against FCLIB's own definition of the global problem and against our solve.
#![allow(clippy::unwrap_used)]

mod common;
use common::signorini;

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fixtures/hard/{name}"))
}

/// Reads the file with h5py and returns what FCLIB's definition says about it (JSON): sizes,
/// the title, and with the stored solution the residuals of M v = H r + f and u = Hᵀv + w, the
/// cone and complementarity conditions per contact, the objective ½vᵀMv − fᵀv, Σ r_N and Σ r_T.
const READER: &str = r#"
import json, sys
import h5py, numpy as np
f = h5py.File(sys.argv[1], "r")
g = f["fclib_global"]
def csc(grp):
    m, n, nz = int(grp["m"][0]), int(grp["n"][0]), int(grp["nz"][0])
    p, i, x = grp["p"][()], grp["i"][()], grp["x"][()]
    assert nz == -1 and len(p) == n + 1 and len(i) == len(x) == int(grp["nzmax"][0])
    cols = np.repeat(np.arange(n), np.diff(p))
    def mul(v):
        out = np.zeros(m)
        np.add.at(out, i, x * v[cols])
        return out
    def mul_t(v):
        out = np.zeros(n)
        np.add.at(out, cols, x * v[i])
        return out
    return m, n, mul, mul_t
nM, _, M, _ = csc(g["M"])
nH, m2, H, Ht = csc(g["H"])
fv, w, mu = g["vectors/f"][()], g["vectors/w"][()], g["vectors/mu"][()]
out = {"spacedim": int(g["spacedim"][0]), "n": nM, "contacts": len(mu), "columns": m2,
       "title": g["info/title"][()].decode().rstrip("\x00"), "mu": sorted(set(mu.tolist()))}
if "solution" in f:
    v, u, r = f["solution/v"][()], f["solution/u"][()], f["solution/r"][()]
    force = max(np.abs(fv).max(), np.abs(H(r)).max())
    out["stationarity"] = float(np.abs(M(v) - H(r) - fv).max() / force)
    out["u_mismatch"] = float(np.abs(Ht(v) + w - u).max())
    rn, rt, un, ut = r[0::2], r[1::2], u[0::2], u[1::2]
    out["min_rn"] = float(rn.min() / force)
    out["cone_excess"] = float((np.abs(rt) - mu * rn).max() / force)
    gap_scale = max(np.abs(w).max(), np.abs(v).max())
    out["min_un"] = float(un.min() / gap_scale)
    out["complementarity"] = float(np.abs(rn * un).max() / (force * gap_scale))
    out["max_rt_ut"] = float((rt * ut).max() / (force * gap_scale))
    # result.json's objective adds the frictional term s|slip| with s = mu r_N (docs/scene.md).
    out["objective"] = float(0.5 * v @ M(v) - fv @ v + (mu * rn * np.abs(ut)).sum())
    out["sum_rn"], out["sum_rt"] = float(rn.sum()), float(rt.sum())
out["max_wt"] = float(np.abs(w[1::2]).max()) if len(w) else 0.0
print(json.dumps(out))
"#;

fn read_back(file: &Path) -> Value {
    let o = Command::new("python3")
        .args(["-c", READER, file.to_str().unwrap()])
        .output()
        .expect("python3 (with h5py: pip install h5py, as .ci/run does)");
    assert!(
        o.status.success(),
        "the reader failed (needs h5py: pip install h5py):\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

fn export_fclib(dir: &Path, scene: &Path, file: &Path) -> std::process::Output {
    let args = [
        "export",
        scene.to_str().unwrap(),
        "--fclib",
        file.to_str().unwrap(),
    ];
    signorini(&args, dir)
}

/// The objective `signorini solve` reports for `scene` (result.json).
fn solved_objective(dir: &Path, scene: &Path) -> f64 {
    let out = dir.join("solved");
    let o = signorini(
        &[
            "solve",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        dir,
    );
    assert!(o.status.success(), "{}", text(&o));
    let result: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    result["objective"].as_f64().unwrap()
}

fn text(o: &std::process::Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// The dragged block (fixtures/hard/friction-slide.toml: every node slides, N = 1e-3, μ = 0.3).
/// FCLIB's conditions hold for the stored answer to the solve's tolerance (1e-9 relative,
/// the residuals' scale: ×10 margin for the reader's own sums), the statics of full slip hold
/// exactly for the discrete model (Σ r_N = N to the tolerance, |Σ r_T| = μ N), and the
/// objective FCLIB's data give, ½vᵀMv − fᵀv + Σ μ r_N |u_T|, is the one `signorini solve`
/// reports (to 1e-10: both are sums of the same numbers, the answers agree to round-off).
#[test]
fn a_coulomb_scene_reads_back_as_fclib_s_global_problem_with_our_answer() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("friction-slide.toml");
    let file = dir.path().join("slide.hdf5");
    let o = export_fclib(dir.path(), &scene, &file);
    assert!(o.status.success(), "{}", text(&o));
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, vec!["slide.hdf5".to_string()], "no temporary left");
    let r = read_back(&file);
    assert_eq!(r["spacedim"], 2);
    assert_eq!(r["columns"], 2 * r["contacts"].as_u64().unwrap());
    assert_eq!(
        r["title"],
        "Hard: block dragged across a base, Coulomb mu = 0.3, full slip"
    );
    assert_eq!(r["mu"], serde_json::json!([0.3]));
    let at_most = |key: &str, bound: f64| {
        let v = r[key].as_f64().unwrap();
        assert!(v <= bound, "{key} = {v:e} > {bound:e}");
    };
    at_most("stationarity", 1e-8);
    at_most("u_mismatch", 1e-15);
    at_most("cone_excess", 1e-8);
    at_most("complementarity", 1e-8);
    at_most("max_rt_ut", 1e-8);
    assert!(r["min_rn"].as_f64().unwrap() >= -1e-8);
    assert!(r["min_un"].as_f64().unwrap() >= -1e-8);
    let (n, t) = (r["sum_rn"].as_f64().unwrap(), r["sum_rt"].as_f64().unwrap());
    assert!((n - 1e-3).abs() < 1e-8 * 1e-3, "Σ r_N = {n:e}, N = 1e-3");
    assert!((t.abs() - 0.3 * n).abs() < 1e-8 * 1e-3, "Σ r_T = {t:e}");

    let ours = solved_objective(dir.path(), &scene);
    let theirs = r["objective"].as_f64().unwrap();
    assert!(
        (ours - theirs).abs() <= 1e-10 * ours.abs(),
        "objective: result.json {ours:e}, FCLIB data {theirs:e}"
    );
}

/// A Tresca pair (a fixed bound, no cone) has no FCLIB form: refused with the reason, exit 1,
/// nothing written.
#[test]
fn scenes_fclib_cannot_state_are_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let tresca = fixture("friction-tresca-mortar.toml");
    let file = dir.path().join("p.hdf5");
    let o = export_fclib(dir.path(), &tresca, &file);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("tresca"), "{}", text(&o));
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(names.is_empty(), "nothing written: {names:?}");
}

/// The dragged block of friction-slide.toml with its drag reached in three increments.
fn stepped_slide(dir: &Path) -> PathBuf {
    let scene = dir.join("stepped.toml");
    let text_of = std::fs::read_to_string(fixture("friction-slide.toml")).unwrap();
    std::fs::write(
        &scene,
        text_of.replace(
            "value = [0.01, 0]\n",
            "name = \"drag\"\nvalue = [0.01, 0]\n",
        ) + "\n[[step]]\nloads = { drag = 1.0 }\nincrements = 3\n",
    )
    .unwrap();
    scene
}

/// A load path: one FCLIB file per increment (`p-00001.hdf5` …, as LMGC90's and Siconos' dumps
/// number a sequence), each read back by h5py.  Each stored answer satisfies FCLIB's conditions
/// of its own file (same tolerances as the single problem above, same reasons); the first
/// increment's tangential w is zero (no history) and the later ones' are not (the previous
/// slip); the last file's FCLIB objective is the one `signorini solve` reports for the path
/// (result.json: the last increment's, to 1e-10 as above); and each increment's file, solved
/// on its own by `compare --fclib` with clarabel (an interior-point method, no warm start from
/// the path), gives the stored answer to 1e-6 relative (both meet the relative residuals 1e-9;
/// M's condition number here is at most ~1e3, see tests/fclib_import.rs).
#[test]
fn a_load_path_is_written_as_one_fclib_problem_per_increment() {
    let dir = tempfile::tempdir().unwrap();
    let scene = stepped_slide(dir.path());
    let file = dir.path().join("p.hdf5");
    let o = export_fclib(dir.path(), &scene, &file);
    assert!(o.status.success(), "{}", text(&o));
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".hdf5"))
        .collect();
    names.sort();
    assert_eq!(names, ["p-00001.hdf5", "p-00002.hdf5", "p-00003.hdf5"]);
    let mut last_objective = 0.0;
    for (k, name) in names.iter().enumerate() {
        let path = dir.path().join(name);
        let r = read_back(&path);
        assert!(
            r["title"]
                .as_str()
                .unwrap()
                .ends_with(&format!("(step 1, increment {})", k + 1)),
            "{}",
            r["title"]
        );
        let at_most = |key: &str, bound: f64| {
            let v = r[key].as_f64().unwrap();
            assert!(v <= bound, "{name}: {key} = {v:e} > {bound:e}");
        };
        at_most("stationarity", 1e-8);
        at_most("u_mismatch", 1e-15);
        at_most("cone_excess", 1e-8);
        at_most("complementarity", 1e-8);
        at_most("max_rt_ut", 1e-8);
        assert!(r["min_rn"].as_f64().unwrap() >= -1e-8, "{name}");
        assert!(r["min_un"].as_f64().unwrap() >= -1e-8, "{name}");
        let history = r["max_wt"].as_f64().unwrap();
        if k == 0 {
            assert_eq!(history, 0.0, "{name}: no slip before the first increment");
        } else {
            assert!(history > 0.0, "{name}: the previous increment's slip");
        }
        last_objective = r["objective"].as_f64().unwrap();

        let out = dir.path().join(format!("cmp-{k}"));
        let o = signorini(
            &[
                "compare",
                "--fclib",
                path.to_str().unwrap(),
                "--backends",
                "clarabel",
                "--out",
                out.to_str().unwrap(),
            ],
            dir.path(),
        );
        assert!(o.status.success(), "{name}: {}", text(&o));
        let report: Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("compare.json")).unwrap())
                .unwrap();
        let row = &report["backends"][0];
        assert_eq!(row["status"], "solved", "{name}: {row}");
        for key in ["v", "r"] {
            let d = row["stored"][key].as_f64().unwrap();
            assert!(d <= 1e-6, "{name}: stored {key} differs by {d:e}");
        }
    }
    let ours = solved_objective(dir.path(), &scene);
    assert!(
        (ours - last_objective).abs() <= 1e-10 * ours.abs(),
        "objective: result.json {ours:e}, the last increment's FCLIB data {last_objective:e}"
    );
}
