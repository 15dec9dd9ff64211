//! Friction from the command line (issue 20): Coulomb and Tresca pairs solved by every backend
//! that solves box rows, checked against statics that hold exactly in the small-displacement
//! model — full slip on a flat base (tangential force μN), sticking below the threshold, the
//! NAFEMS-type incline F/G = (tan α + μ)/(1 − μ tan α) — and refusals of bad friction keys.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used)]

mod common;

use std::path::Path;

use common::{json, signorini, succeeded};
use serde_json::Value;
use signorini::backends::BackendKind;

/// Every backend of this build and `auto`: each solves box rows.
fn backends() -> Vec<&'static str> {
    std::iter::once("auto")
        .chain(
            BackendKind::ALL
                .into_iter()
                .filter(|k| k.available())
                .map(BackendKind::name),
        )
        .collect()
}

/// KKT tolerance of the runs.  The statics below hold exactly for the discrete model, so the
/// force ratios are as accurate as the answers: within ~10 × tol of the loads (the residuals are
/// relative to the force scale, the ratios divide two forces of that scale).
const TOL: &str = "1e-10";

/// A base [0, 4] × [0, 1] clamped at the bottom and a block [1, 2] × [1, 2] on it (non-matching
/// meshes: h 0.25 and 0.2), pressed by a uniform traction p = 1e-3 on its top (N = 1e-3); `extra`
/// adds the drag and `contact` the pair's keys.
fn flat(contact: &str, extra: &str) -> String {
    format!(
        r#"title = "block on a flat base"
[[body]]
name = "base"
polygon = [[0, 0], [4, 0], [4, 1], [0, 1]]
hmax = 0.25
young = 1.0
poisson = 0.3
[[body]]
name = "block"
polygon = [[1, 1], [2, 1], [2, 2], [1, 2]]
hmax = 0.2
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "base"
region = [0, 4, 0, 0]
{extra}
[[contact]]
bodies = ["block", "base"]
region = [0.9, 2.1, 0.99, 1.01]
{contact}
"#
    )
}

/// The block's left side pushed 0.01 along x (its y free): far beyond the elastic shear of the
/// block (strains ~1e-3), so every contact node slides.
const DRAGGED: &str = r#"[[dirichlet]]
body = "block"
region = [1, 1, 1.01, 2]
value = [0.01, 0]
components = ["x"]
[[neumann]]
body = "block"
region = [1, 2, 2, 2]
traction = [0, -1e-3]"#;

fn solve(dir: &Path, scene: &str, backend: &str) -> Value {
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    let out = dir.join(format!("out-{backend}"));
    let o = signorini(
        &[
            "solve",
            "scene.toml",
            "--backend",
            backend,
            "--tol",
            TOL,
            "--out",
            out.to_str().unwrap(),
        ],
        dir,
    );
    succeeded(&o);
    json(&out.join("result.json"))
}

fn body<'a>(r: &'a Value, name: &str) -> &'a Value {
    r["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["name"] == name)
        .unwrap()
}

fn states(pair: &Value) -> Vec<String> {
    pair["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n["state"].as_str().unwrap().to_string())
        .collect()
}

#[test]
fn a_dragged_block_slides_with_tangential_force_mu_n_on_every_backend_and_formulation() {
    let dir = tempfile::tempdir().unwrap();
    for formulation in ["node-to-segment", "mortar"] {
        for mu in [0.1, 0.3] {
            let scene = flat(
                &format!("friction = {mu}\nformulation = \"{formulation}\""),
                DRAGGED,
            );
            for backend in backends() {
                let r = solve(dir.path(), &scene, backend);
                let what = format!("{formulation}, μ = {mu}, {backend}");
                assert_eq!(r["status"], "solved", "{what}");
                let pair = &r["contacts"][0];
                let n = pair["normal_force"].as_f64().unwrap();
                let t = pair["tangential_force"].as_f64().unwrap();
                // N = p × 1 = 1e-3 (the block's vertical balance); |T| = μN at full slip.
                assert!((n - 1e-3).abs() < 1e-11, "{what}: N = {n}");
                assert!(
                    (t.abs() - mu * n).abs() < 1e-8 * n,
                    "{what}: T = {t}, N = {n}"
                );
                assert!(states(pair).iter().all(|s| s == "slip"), "{what}: {pair}");
                // The push needed is the friction force: the block's x reaction is μN.
                let push = body(&r, "block")["reaction"][0].as_f64().unwrap();
                assert!(
                    (push - mu * 1e-3).abs() < 1e-8 * 1e-3,
                    "{what}: push {push}"
                );
                assert_eq!(pair["friction"]["coulomb"], mu, "{what}");
                assert!(r["coulomb"]["converged"].as_bool().unwrap(), "{what}");
            }
        }
    }
}

#[test]
fn a_block_held_sideways_by_friction_alone_sticks_below_the_threshold() {
    // Floating block (no support at all) pressed by P = 1e-3 and dragged by Q = 1e-4 on its
    // top, μ = 1: Q/P = 0.1 ≪ μ, so every node sticks and the friction carries Q exactly.
    let dir = tempfile::tempdir().unwrap();
    let load = "[[neumann]]\nbody = \"block\"\nregion = [1, 2, 2, 2]\ntraction = [1e-4, -1e-3]";
    for (contact, law) in [("friction = 1.0", "coulomb"), ("tresca = 0.5", "tresca")] {
        let scene = flat(contact, load);
        for backend in backends() {
            let r = solve(dir.path(), &scene, backend);
            let what = format!("{contact}, {backend}");
            assert_eq!(r["status"], "solved", "{what}");
            let pair = &r["contacts"][0];
            let t = pair["tangential_force"].as_f64().unwrap();
            assert!((t.abs() - 1e-4).abs() < 1e-8 * 1e-3, "{what}: T = {t}");
            assert!(states(pair).iter().all(|s| s == "stick"), "{what}: {pair}");
            assert!(pair["friction"][law].is_number(), "{what}");
        }
    }
}

#[test]
fn tresca_bounds_the_tangential_traction_at_every_sliding_node() {
    // Tresca s = 2e-4 (a traction): with the block dragged, every node slides at |λₜ| = s ×
    // its tributary length, so the tangential traction is ±s everywhere and T = s × 1.
    let dir = tempfile::tempdir().unwrap();
    let scene = flat("tresca = 2e-4", DRAGGED);
    let mut answers = Vec::new();
    for backend in backends() {
        let r = solve(dir.path(), &scene, backend);
        assert_eq!(r["status"], "solved", "{backend}");
        let pair = &r["contacts"][0];
        for node in pair["nodes"].as_array().unwrap() {
            let q = node["tangential_traction"].as_f64().unwrap();
            assert!((q.abs() - 2e-4).abs() < 1e-8 * 1e-3, "{backend}: {node}");
            assert_eq!(node["state"], "slip", "{backend}: {node}");
        }
        let t = pair["tangential_force"].as_f64().unwrap();
        assert!((t.abs() - 2e-4).abs() < 1e-8 * 1e-3, "{backend}: T = {t}");
        assert!(r.get("coulomb").is_none(), "Tresca needs no fixed point");
        answers.push((backend, r));
    }
    // Every backend's displacements agree (the Tresca problem is one convex QP with a unique
    // answer): the block's largest displacement to 1e-6 relative.
    let reference = body(&answers[0].1, "block")["max_displacement"]
        .as_f64()
        .unwrap();
    for (backend, r) in &answers {
        let d = body(r, "block")["max_displacement"].as_f64().unwrap();
        assert!(
            (d - reference).abs() < 1e-6 * reference,
            "{backend}: {d} vs {reference}"
        );
    }
}

/// The NAFEMS-type frictional patch test on an incline: a base whose top rises with slope
/// tan α = 0.1, a block on it (non-matching meshes) pressed by a vertical traction (G) and
/// pushed horizontally at its left side until it slides up the slope.
fn incline(mu: f64, formulation: &str) -> String {
    format!(
        r#"title = "incline"
[[body]]
name = "base"
polygon = [[0, 0], [4, 0], [4, 1.4], [0, 1.0]]
hmax = 0.25
young = 1.0
poisson = 0.3
[[body]]
name = "block"
polygon = [[1, 1.1], [2, 1.2], [2, 2.2], [1, 2.1]]
hmax = 0.15
young = 1.0
poisson = 0.3
[[dirichlet]]
body = "base"
region = [0, 4, 0, 0]
[[dirichlet]]
body = "block"
region = [1, 1, 1.11, 2.1]
value = [0.01, 0]
components = ["x"]
[[neumann]]
body = "block"
region = [1, 2, 2.1, 2.2]
traction = [0, -1e-3]
[[contact]]
bodies = ["block", "base"]
region = [0.9, 2.1, 1.05, 1.25]
formulation = "{formulation}"
{friction}
"#,
        friction = if mu > 0.0 {
            format!("friction = {mu}")
        } else {
            String::new()
        }
    )
}

#[test]
fn pushing_a_block_up_an_incline_takes_f_over_g_as_the_statics_of_sliding_say() {
    let dir = tempfile::tempdir().unwrap();
    let tan = 0.1_f64;
    for formulation in ["node-to-segment", "mortar"] {
        for mu in [0.0, 0.1, 0.2, 0.3] {
            // Sliding up the slope: F = N sin α + μ N cos α, G = N cos α − μ N sin α
            // (0.412371 at μ = 0.3, the NAFEMS value).
            let expected = (tan + mu) / (1.0 - mu * tan);
            let r = solve(dir.path(), &incline(mu, formulation), "auto");
            let what = format!("{formulation}, μ = {mu}");
            assert_eq!(r["status"], "solved", "{what}");
            let block = body(&r, "block");
            let f = block["reaction"][0].as_f64().unwrap();
            let g = -block["applied"][1].as_f64().unwrap();
            // The issue asks for 0.1 % (published codes reach 0.05 %); the discrete statics are
            // exact, so the ratio is held to 1e-7 (solver tolerance × the slope's leverage).
            assert!(
                (f / g - expected).abs() < 1e-7 * expected.max(0.1),
                "{what}: F/G = {}, expected {expected}",
                f / g
            );
            if mu > 0.0 {
                let pair = &r["contacts"][0];
                assert!(
                    states(pair).iter().all(|s| s != "stick"),
                    "{what}: every node in contact slides: {pair}"
                );
            }
        }
    }
}

#[test]
fn zero_friction_is_the_frictionless_pair_and_bad_friction_keys_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let plain = solve(dir.path(), &flat("", DRAGGED), "auto");
    for zero in ["friction = 0", "tresca = 0.0"] {
        let r = solve(dir.path(), &flat(zero, DRAGGED), "auto");
        assert_eq!(
            r["constraints"], plain["constraints"],
            "{zero}: no tangential rows"
        );
        assert!(r["contacts"][0].get("friction").is_none(), "{zero}");
        assert!(
            r["contacts"][0]["nodes"][0].get("state").is_none(),
            "{zero}"
        );
        assert_eq!(
            r["contacts"][0]["normal_force"],
            plain["contacts"][0]["normal_force"]
        );
    }
    for (keys, named) in [
        ("friction = -0.1", "friction"),
        ("tresca = -1e-3", "tresca"),
        ("friction = nan", "friction"),
        ("tresca = inf", "tresca"),
        ("friction = 0.3\ntresca = 1e-3", "tresca"),
    ] {
        std::fs::write(dir.path().join("bad.toml"), flat(keys, DRAGGED)).unwrap();
        let out = dir.path().join("bad-out");
        let o = signorini(
            &["solve", "bad.toml", "--out", out.to_str().unwrap()],
            dir.path(),
        );
        assert_eq!(o.status.code(), Some(1), "{keys}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(named) && err.contains("contact #1"),
            "{keys}: {err}"
        );
        assert!(!out.exists(), "{keys}: nothing written");
    }
}

/// The dragged block with named loads (`press`, `push`) and the given `[[step]]` tables.
fn dragged_with_steps(contact: &str, steps: &str) -> String {
    let named = DRAGGED
        .replace(
            "[[dirichlet]]\nbody = \"block\"",
            "[[dirichlet]]\nname = \"push\"\nbody = \"block\"",
        )
        .replace(
            "[[neumann]]\nbody = \"block\"",
            "[[neumann]]\nname = \"press\"\nbody = \"block\"",
        );
    format!("{}\n{steps}", flat(contact, &named))
}

#[test]
fn coulomb_friction_remembers_the_direction_of_the_last_slide() {
    // Pushed 0.01 to the right, then back to 0.005: the block last slid to the left, so the
    // friction force points right and the push that holds it is −μN.  Solved in one step at
    // 0.005 from the reference, the block slides right and the push is +μN.  Statics are exact
    // at full slip: |F| = μN either way, only the history sets the sign.
    let dir = tempfile::tempdir().unwrap();
    let mu = 0.3;
    let there_and_back = dragged_with_steps(
        "friction = 0.3",
        "[[step]]\nloads = { press = 1.0, push = 1.0 }\nincrements = 2\n\
         [[step]]\nloads = { press = 1.0, push = 0.5 }\nincrements = 2",
    );
    let straight = dragged_with_steps(
        "friction = 0.3",
        "[[step]]\nloads = { press = 1.0, push = 0.5 }",
    );
    for (scene, sign) in [(there_and_back, -1.0), (straight, 1.0)] {
        for backend in ["auto", "clarabel"] {
            let r = solve(dir.path(), &scene, backend);
            assert_eq!(r["status"], "solved", "{backend}");
            let push = body(&r, "block")["reaction"][0].as_f64().unwrap();
            assert!(
                (push - sign * mu * 1e-3).abs() < 1e-8 * 1e-3,
                "{backend}: push {push}, expected {}",
                sign * mu * 1e-3
            );
            let steps = r["steps"].as_array().map_or(0, Vec::len);
            assert_eq!(steps, if sign < 0.0 { 4 } else { 0 }, "{backend}");
            assert!(
                states(&r["contacts"][0]).iter().all(|s| s == "slip"),
                "{backend}"
            );
        }
    }
}

#[test]
fn a_frictionless_load_path_ends_where_the_single_step_solve_is() {
    // Without friction the answer depends only on the final loads: pressing first, then
    // pushing (the push's prescribed value ramped through 0, 0.5, 1) must end at the one-step
    // answer, to the solver's tolerance.
    let dir = tempfile::tempdir().unwrap();
    let path = dragged_with_steps(
        "",
        "[[step]]\nloads = { press = 1.0 }\nincrements = 2\n\
         [[step]]\nloads = { press = 1.0, push = 1.0 }\nincrements = 2",
    );
    let r = solve(dir.path(), &path, "auto");
    let one = solve(dir.path(), &flat("", DRAGGED), "auto");
    assert_eq!(r["status"], "solved");
    assert_eq!(r["steps"].as_array().unwrap().len(), 4);
    for name in ["block", "base"] {
        let (a, b) = (body(&r, name), body(&one, name));
        for key in ["max_displacement", "max_von_mises"] {
            let (x, y) = (a[key].as_f64().unwrap(), b[key].as_f64().unwrap());
            assert!((x - y).abs() < 1e-7 * y.abs(), "{name} {key}: {x} vs {y}");
        }
    }
}

/// Found in stop 30: the report's `applied` loads were the full tractions whatever the load
/// path's last factors, so a path ending at half the press wrote `force_balance` 0.5 for an
/// answer that balances.  The written results are the last increment's, so `applied` is the
/// press's traction resultant at its last factor: 0.5 × p × width = 0.5 × 1e-3 × 1 (exact:
/// a uniform traction on a straight edge), and the three figures balance to the solver's
/// tolerance (~10 × tol of the load, as above).
#[test]
fn the_applied_loads_are_those_of_the_path_s_last_factors() {
    let dir = tempfile::tempdir().unwrap();
    let path = dragged_with_steps(
        "friction = 0.3",
        "[[step]]\nloads = { press = 1.0, push = 1.0 }\nincrements = 2\n\
         [[step]]\nloads = { press = 0.5, push = 1.0 }\nincrements = 2",
    );
    let r = solve(dir.path(), &path, "auto");
    assert_eq!(r["status"], "solved");
    let applied = body(&r, "block")["applied"][1].as_f64().unwrap();
    assert!(
        (applied + 0.5e-3).abs() < 1e-15,
        "block's applied y load {applied:e}, expected -5e-4"
    );
    let balance = r["force_balance"].as_f64().unwrap();
    assert!(balance < 1e-8, "force_balance {balance:e}");
}

#[test]
fn load_paths_with_bad_names_or_increments_are_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    for (steps, named) in [
        ("[[step]]\nloads = { pres = 1.0 }", "pres"),
        (
            "[[step]]\nloads = { press = 1.0 }\nincrements = 0",
            "increments",
        ),
        ("[[step]]\nloads = { press = inf }", "loads"),
    ] {
        let scene = dragged_with_steps("friction = 0.3", steps);
        std::fs::write(dir.path().join("bad.toml"), &scene).unwrap();
        let out = dir.path().join("bad-out");
        let o = signorini(
            &["solve", "bad.toml", "--out", out.to_str().unwrap()],
            dir.path(),
        );
        assert_eq!(o.status.code(), Some(1), "{steps}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("step #1") && err.contains(named),
            "{steps}: {err}"
        );
        assert!(!out.exists());
    }
    let twice = dragged_with_steps("", "").replace("name = \"press\"", "name = \"push\"");
    std::fs::write(dir.path().join("twice.toml"), twice).unwrap();
    let o = signorini(&["solve", "twice.toml", "--out", "x"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("\"push\" is used twice"), "{err}");
}

#[test]
fn the_frictional_hard_fixtures_carry_their_exact_tangential_forces() {
    // (fixture, |tangential force| from statics, every node's state): full slip gives μN (N the
    // pressure times the block's width 1), sticking carries the sideways load exactly.
    let cases = [
        ("friction-slide", 0.3 * 1e-3, "slip"),
        ("friction-mu-range", 0.01 * 1e-3, "slip"),
        ("friction-tresca-mortar", 2e-4, "slip"),
        ("friction-si", 0.2 * 1e6, "slip"),
        ("friction-stick", 1e-4, "stick"),
        ("friction-mu-high", 1e-4, "stick"),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (name, force, state) in cases {
        let scene =
            std::fs::read_to_string(common::repo(&format!("fixtures/hard/{name}.toml"))).unwrap();
        for backend in ["auto", "pdas", "dual-ssn"] {
            let r = solve(dir.path(), &scene, backend);
            assert_eq!(r["status"], "solved", "{name} {backend}");
            let pair = &r["contacts"][0];
            let t = pair["tangential_force"].as_f64().unwrap();
            // 1e-8 of the normal force: the tolerance 1e-10 of the run, with margin.
            let n = pair["normal_force"].as_f64().unwrap();
            assert!(
                (t.abs() - force).abs() < 1e-8 * n,
                "{name} {backend}: T = {t}"
            );
            assert!(
                states(pair).iter().all(|s| s == state),
                "{name} {backend}: {:?}",
                states(pair)
            );
        }
    }
}

#[test]
fn newton_is_refused_by_a_backend_without_it_and_the_fixed_point_is_not() {
    // `--coulomb newton` asks for a backend's own method: dual-pgs has none and says so (no
    // silent fixed point), nothing is written; `--coulomb fixed-point` runs through it.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("scene.toml"),
        flat("friction = 0.3", DRAGGED),
    )
    .unwrap();
    let refused = signorini(
        &[
            "solve",
            "scene.toml",
            "--backend",
            "dual-pgs",
            "--coulomb",
            "newton",
            "--out",
            "refused",
        ],
        dir.path(),
    );
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success());
    assert!(err.contains("dual-pgs") && err.contains("Coulomb"), "{err}");
    assert!(!dir.path().join("refused/result.json").exists());
    let typo = signorini(&["solve", "scene.toml", "--coulomb", "newtn"], dir.path());
    let err = String::from_utf8_lossy(&typo.stderr);
    assert!(
        !typo.status.success() && err.contains("fixed-point"),
        "{err}"
    );
    let o = signorini(
        &[
            "solve",
            "scene.toml",
            "--backend",
            "dual-pgs",
            "--coulomb",
            "fixed-point",
            "--out",
            "fp",
        ],
        dir.path(),
    );
    succeeded(&o);
    let r = json(&dir.path().join("fp/result.json"));
    assert_eq!(r["coulomb"]["method"], "fixed-point");
    assert_eq!(r["provenance"]["settings"]["coulomb"], "fixed-point");
}

/// The frictional fixtures of issue 41 that a user writes first — a floating block held
/// sideways by friction with partial slip, a cap pressed then dragged in two load steps — each
/// with its pair's forces fixed by statics (N = 1e-3, T = −1e-4: nothing else holds the body).
const PARTIAL_SLIP: [&str; 4] = [
    "friction-float-tresca",
    "friction-float-coulomb",
    "friction-cap-tresca",
    "friction-cap-coulomb",
];

/// `signorini solve` of fixture `name` through `backend` at tol 1e-9: the exit code and, when
/// results were written (exit 0 or 2), result.json.
fn solve_fixture(dir: &Path, name: &str, backend: &str) -> (Option<i32>, Option<Value>) {
    let scene = common::repo(&format!("fixtures/hard/{name}.toml"));
    let out = dir.join(format!("{name}-{backend}"));
    let o = signorini(
        &[
            "solve",
            scene.to_str().unwrap(),
            "--backend",
            backend,
            "--tol",
            "1e-9",
            "--time-limit",
            "20",
            "--out",
            out.to_str().unwrap(),
        ],
        dir,
    );
    let result = out.join("result.json");
    (o.status.code(), result.exists().then(|| json(&result)))
}

#[test]
fn partial_slip_fixtures_balance_their_loads_on_every_backend_that_solves_them() {
    // Every backend either answers `solved` with the statics of a body held by contact alone
    // (N = 1e-3, T = −1e-4 within 1e-8 N: the tolerance 1e-9 of forces of that scale, with
    // margin) and the same displacements as the others, or ends with another status and exit
    // 2 — never a `solved` that breaks them.  The default solves each.
    let dir = tempfile::tempdir().unwrap();
    for name in PARTIAL_SLIP {
        let mut reference: Option<(String, f64)> = None;
        let mut solved = Vec::new();
        for backend in backends() {
            if backend == "dual-uzawa" {
                continue; // its time-outs on every one of these (expected failures) add minutes
            }
            let (code, r) = solve_fixture(dir.path(), name, backend);
            let r = r.unwrap_or_else(|| panic!("{name} {backend}: no result.json (exit {code:?})"));
            if r["status"] != "solved" {
                assert_eq!(code, Some(2), "{name} {backend}: {}", r["status"]);
                continue;
            }
            assert_eq!(code, Some(0), "{name} {backend}");
            solved.push(backend);
            let pair = &r["contacts"][0];
            let n = pair["normal_force"].as_f64().unwrap();
            let t = pair["tangential_force"].as_f64().unwrap();
            assert!((n - 1e-3).abs() < 1e-11, "{name} {backend}: N = {n:e}");
            assert!((t + 1e-4).abs() < 1e-11, "{name} {backend}: T = {t:e}");
            let u = r["probes"][0]["displacement"][0].as_f64().unwrap();
            match &reference {
                None => reference = Some((backend.to_string(), u)),
                // The probe's x displacement (the friction's lever on the body): 1e-6
                // relative, what √(m·tol) of the energy-norm argument gives with margin.
                Some((first, v)) => assert!(
                    (u - v).abs() <= 1e-6 * v.abs(),
                    "{name}: {backend}'s probe ux {u:e} against {first}'s {v:e}"
                ),
            }
            if name.starts_with("friction-float") {
                let states = states(pair);
                assert!(
                    states.iter().any(|s| s == "stick") && states.iter().any(|s| s == "slip"),
                    "{name} {backend}: partial slip expected, got {states:?}"
                );
            }
        }
        assert!(solved.contains(&"auto"), "{name}: solved by {solved:?}");
    }
}

#[test]
fn both_semismooth_newton_backends_solve_the_floating_block_and_the_coulomb_cap() {
    // dual-ssn ended `numerical-error` on the Coulomb block (issue 41): its set predicted every
    // tangential row slipping, which leaves the block's sideways motion unheld (a singular
    // system); now the least excessive slip sticks until the modes are held.
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "friction-float-tresca",
        "friction-float-coulomb",
        "friction-cap-coulomb",
    ] {
        for backend in ["pdas", "dual-ssn"] {
            let (code, r) = solve_fixture(dir.path(), name, backend);
            let status = r.map(|r| r["status"].clone());
            assert_eq!(
                status.as_ref().and_then(Value::as_str),
                Some("solved"),
                "{name} {backend} (exit {code:?})"
            );
        }
    }
}

#[test]
#[ignore = "issue 41 item 1 open: on the Tresca cap pdas's active sets cycle (its interior-point continuation knows one-sided rows only) and dual-ssn's set rule cycles (no merit function or line search yet)"]
fn both_semismooth_newton_backends_solve_the_tresca_cap() {
    let dir = tempfile::tempdir().unwrap();
    for backend in ["pdas", "dual-ssn"] {
        let (_, r) = solve_fixture(dir.path(), "friction-cap-tresca", backend);
        let status = r.map(|r| r["status"].clone());
        assert_eq!(
            status.as_ref().and_then(Value::as_str),
            Some("solved"),
            "{backend}"
        );
    }
}
