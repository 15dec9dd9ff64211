//! What the driver's integration tests share: running the built `signorini` binary.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The standard output of a run that must have succeeded (exit 0); otherwise fails showing both
/// streams.
pub fn succeeded(o: &Output) -> String {
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    stdout
}

/// Runs the `signorini` binary built for these tests with `args` in `cwd`.
pub fn signorini(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run signorini")
}

/// `path` relative to the repository's root.
pub fn repo(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

/// The JSON file at `path`, parsed.
pub fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("read")).expect("JSON")
}

/// Two unit blocks, the upper one pushed down onto the lower, clamped one; `young`, the traction
/// and the upper block's prescribed x-displacement are the knobs.
pub fn blocks(young: &str, traction: &str, value: &str) -> String {
    format!(
        r#"title = "blocks"
[[body]]
name = "upper"
polygon = [[0, 1], [1, 1], [1, 2], [0, 2]]
hmax = 0.5
young = {young}
poisson = 0.3
[[body]]
name = "lower"
polygon = [[0, 0], [1, 0], [1, 1], [0, 1]]
hmax = 0.5
young = {young}
poisson = 0.3
[[dirichlet]]
body = "lower"
region = [0, 1, 0, 0]
[[dirichlet]]
body = "upper"
region = [0, 0, 1, 2]
components = ["x"]
value = [{value}, 0]
[[neumann]]
body = "upper"
region = [0, 1, 2, 2]
traction = [0, {traction}]
[[contact]]
bodies = ["upper", "lower"]
"#
    )
}

/// The contact patch test: a unit block ("top", [0,1]×[1,2], Young's modulus `young.0`) on a
/// unit block ("base", [0,1]×[0,1], `young.1`),
/// [0,1]×[0,1]), ν = 0, the base's bottom held in y, both left edges held in x, the top edge
/// moved down by δ = `delta`.  With ν = 0 the exact solution is uniaxial: σ_yy = −p in both blocks, each
/// shortening by p × height / E, so δ = p (1/E_top + 1/E_base) (heights 1) and
/// p = δ / (1/E_top + 1/E_base); the transmitted force is p × width 1.  No lateral motion, so
/// the rollers are compatible.  Linear displacements lie in the P1 and Q1 spaces: a method
/// passing the patch test reproduces them exactly.
pub fn patch_scene(
    h_top: f64,
    h_base: f64,
    element: &str,
    formulation: &str,
    young: (f64, f64),
    delta: f64,
) -> String {
    let (e_top, e_base) = young;
    format!(
        r#"
        [[body]]
        name = "top"
        polygon = [[0, 1], [1, 1], [1, 2], [0, 2]]
        hmax = {h_top}
        element = "{element}"
        young = {e_top}
        poisson = 0.0
        [[body]]
        name = "base"
        polygon = [[0, 0], [1, 0], [1, 1], [0, 1]]
        hmax = {h_base}
        element = "{element}"
        young = {e_base}
        poisson = 0.0
        [[dirichlet]]
        body = "base"
        region = [0, 1, 0, 0]
        components = ["y"]
        [[dirichlet]]
        body = "base"
        region = [0, 0, 0, 1]
        components = ["x"]
        [[dirichlet]]
        body = "top"
        region = [0, 0, 1, 2]
        components = ["x"]
        [[dirichlet]]
        body = "top"
        region = [0, 1, 2, 2]
        value = [0, -{delta}]
        components = ["y"]
        [[contact]]
        bodies = ["top", "base"]
        region = [0, 1, 0.99, 1.01]
        formulation = "{formulation}"
        "#
    )
}

/// The Hertz cap's polygon as `scripts/hertz-scene.py` writes it (R = 1, cap 0.6 high, centre
/// x = 0.8, contact line y = 0.8): vertices every `fine` of arc length where |x − 0.8| ≤ 0.15
/// (`--fine-width`), every 0.02 (`--arc-coarse`) beyond, the two ends on the cap's top line.
pub fn hertz_cap_polygon(fine: f64) -> Vec<[f64; 2]> {
    let (r, height, cx, base) = (1.0_f64, 0.6_f64, 0.8_f64, 0.8_f64);
    let phi0 = ((r - height) / r).acos();
    let phi_f = (0.15 / r).asin();
    let n_f = (2.0 * phi_f * r / fine).ceil() as usize;
    let n_c = ((phi0 - phi_f) * r / 0.02).ceil() as usize;
    let mut t: Vec<f64> = (0..n_c)
        .map(|i| -phi0 + (phi0 - phi_f) * i as f64 / n_c as f64)
        .collect();
    t.extend((0..=n_f).map(|i| -phi_f + 2.0 * phi_f * i as f64 / n_f as f64));
    t.extend((1..=n_c).map(|i| phi_f + (phi0 - phi_f) * i as f64 / n_c as f64));
    let mut pts: Vec<[f64; 2]> = t
        .iter()
        .map(|t| [cx + r * t.sin(), base + r - r * t.cos()])
        .collect();
    let n = pts.len();
    pts[0][1] = base + height;
    pts[n - 1][1] = base + height;
    pts
}

/// The displacement of the report's probe `name` (the probe must exist).
pub fn probe(report: &signorini_core::report::RunReport, name: &str) -> [f64; 2] {
    report
        .probes
        .iter()
        .find(|p| p.name == name)
        .expect("the scene names this probe")
        .displacement
}

/// The run report of `solution` as `signorini solve` writes it (no timings), its residual
/// verdicts judged at `tol`.
pub fn report_of(
    scene: &signorini_core::scene::Scene,
    model: &signorini_core::model::Model,
    solution: &signorini_core::solve::Solution,
    tol: f64,
) -> signorini_core::report::RunReport {
    let fields = signorini_core::report::body_fields(model, solution);
    signorini_core::report::run_report(
        scene,
        model,
        solution,
        &fields,
        tol,
        signorini_core::report::Timings::default(),
    )
}
