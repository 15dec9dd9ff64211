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

    let out = dir.path().join("solved");
    let o = signorini(
        &[
            "solve",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let result: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let ours = result["objective"].as_f64().unwrap();
    let theirs = r["objective"].as_f64().unwrap();
    assert!(
        (ours - theirs).abs() <= 1e-10 * ours.abs(),
        "objective: result.json {ours:e}, FCLIB data {theirs:e}"
    );
}

/// A Tresca pair (a fixed bound, no cone) and a load path (history) have no FCLIB form: refused
/// with the reason, exit 1, nothing written.
#[test]
fn scenes_fclib_cannot_state_are_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let tresca = fixture("friction-tresca-mortar.toml");
    let stepped = dir.path().join("stepped.toml");
    let text_of = std::fs::read_to_string(fixture("friction-slide.toml")).unwrap();
    std::fs::write(
        &stepped,
        text_of.replace("[[neumann]]\n", "[[neumann]]\nname = \"press\"\n")
            + "\n[[step]]\nloads = { press = 1.0 }\n",
    )
    .unwrap();
    for (scene, word) in [(tresca, "tresca"), (stepped, "[[step]]")] {
        let file = dir.path().join("p.hdf5");
        let o = export_fclib(dir.path(), &scene, &file);
        assert_eq!(o.status.code(), Some(1), "{}", text(&o));
        assert!(text(&o).contains(word), "{word}: {}", text(&o));
        assert!(!file.exists(), "nothing written");
    }
}
