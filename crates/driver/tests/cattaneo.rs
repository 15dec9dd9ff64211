//! Cattaneo–Mindlin partial slip (issue 20, validation 3): the Hertz cylinder of
//! `fixtures/accuracy/hertz-graded.toml` (both bodies E = 1, ν = 0.3: elastically similar, so
//! normal and tangential problems do not couple — Dundurs' β = 0), pressed first and then shifted
//! sideways with Coulomb friction μ = 0.3.  Johnson (1985), §7.1, in 2-D: with P and Q < μP per
//! unit length and a = √(4PR/(πE*)), p₀ = 2P/(πa), the stick zone is |x| < c = a √(1 − Q/(μP))
//! and the tangential traction q(x) = μ p₀/a (√(a² − x²) − √(c² − x²)) for |x| < c, μ p(x) for
//! c < |x| < a.  The top of the cap is moved rigidly (prescribed uy, then ux): no tilt.  The
//! traction profile's 3 % rms is checked on two equal cylinders instead (mirror images, meshes
//! built at test time by `mirror/mod.rs`), where the normal and tangential problems decouple.

// Test code: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used)]

mod common;
mod mirror;

use common::{json, repo, signorini, succeeded};
use serde_json::Value;

const MU: f64 = 0.3;
/// Both bodies E = 1, ν = 0.3, plane strain: E* = E / (2 (1 − ν²)).
const E_STAR: f64 = 1.0 / (2.0 * (1.0 - 0.09));
/// The cylinder's radius and the centre of the contact.
const R: f64 = 1.0;
const CENTRE: f64 = 0.8;

/// The graded Hertz scene with the cap's top prescribed (`press`: uy = −0.002, `shift`: ux =
/// 0.0005), friction on the pair (mortar, the flat block as slave: issue 21 found the curved
/// slave's mortar pressure oscillating) and the given `[[step]]` tables.
fn scene(steps: &str) -> String {
    let text = std::fs::read_to_string(repo("fixtures/accuracy/hertz-graded.toml")).unwrap();
    let head = &text[..text.find("[[dirichlet]]\nbody = \"cap\"").unwrap()];
    let top = "[-0.11651513899116794, 1.7165151389911681, 1.4, 1.4]";
    format!(
        r#"{head}[[dirichlet]]
name = "press"
body = "cap"
region = {top}
components = ["y"]
value = [0.0, -0.002]

[[dirichlet]]
name = "shift"
body = "cap"
region = {top}
components = ["x"]
value = [0.0005, 0.0]

[[contact]]
bodies = ["cap", "block"]
region = [0.6, 1.0, 0.79, 0.83]
slave = "block"
formulation = "mortar"
friction = {MU}

{steps}"#
    )
}

/// Normal then tangential loading, the classic Cattaneo path.
const PRESS_THEN_SHIFT: &str = "[[step]]\nloads = { press = 1.0 }\n\
    [[step]]\nloads = { press = 1.0, shift = 1.0 }\nincrements = 2";

/// The pair's nodes as (x − centre, state, q, p), sorted by x.
fn nodes(pair: &Value) -> Vec<(f64, String, f64, f64)> {
    let mut list: Vec<(f64, String, f64, f64)> = pair["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| {
            (
                n["x"].as_f64().unwrap() - CENTRE,
                n["state"].as_str().unwrap().to_string(),
                n["tangential_traction"].as_f64().unwrap(),
                n["pressure"].as_f64().unwrap(),
            )
        })
        .collect();
    list.sort_by(|a, b| a.0.total_cmp(&b.0));
    list
}

/// Solves `scene` with the default backend and returns result.json.
fn run(scene: &str) -> Value {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.toml"), scene).unwrap();
    succeeded(&signorini(
        &["solve", "scene.toml", "--out", "out"],
        dir.path(),
    ));
    json(&dir.path().join("out/result.json"))
}

/// (a, p₀, c) of Hertz and Cattaneo for the computed P and Q.
fn theory(pair: &Value) -> (f64, f64, f64) {
    theory_for(pair, R)
}

/// (a, p₀, c) for the relative radius `r_star` (1/R* = 1/R₁ + 1/R₂).
fn theory_for(pair: &Value, r_star: f64) -> (f64, f64, f64) {
    let p = pair["normal_force"].as_f64().unwrap();
    let q = pair["tangential_force"].as_f64().unwrap().abs();
    let a = (4.0 * p * r_star / (std::f64::consts::PI * E_STAR)).sqrt();
    let p0 = 2.0 * p / (std::f64::consts::PI * a);
    (a, p0, a * (1.0 - q / (MU * p)).sqrt())
}

/// Cattaneo's |q(x)|.
fn cattaneo(x: f64, a: f64, p0: f64, c: f64) -> f64 {
    let root = |r: f64| (r * r - x * x).max(0.0).sqrt();
    if x.abs() < c {
        MU * p0 / a * (root(a) - root(c))
    } else {
        MU * p0 / a * root(a)
    }
}

#[test]
fn pressed_then_shifted_the_stick_zone_has_cattaneo_s_half_width() {
    let r = run(&scene(PRESS_THEN_SHIFT));
    assert_eq!(r["status"], "solved");
    assert_eq!(r["steps"].as_array().unwrap().len(), 3);
    let pair = &r["contacts"][0];
    let (a, p0, c) = theory(pair);
    let list = nodes(pair);
    // The stick half-width on each side: half-way between the outermost sticking node and the
    // innermost slipping one.  Tolerance 2 % (the issue's): the zone's mesh size is 0.002 =
    // a/16, so a node's position alone resolves c to 0.001 = 4.7 % of it; the midpoint halves
    // that, and the states decide which side of c each node lies.
    for side in [-1.0, 1.0] {
        let measured = stick_half_width(&list, side);
        assert!(
            (measured - c).abs() < 0.02 * c,
            "side {side}: c = {measured}, Cattaneo {c} (a = {a})"
        );
    }
    // Hertz's pressure under the same mesh, as a check of the normal problem: within 1 % of p₀
    // at every node inside 0.9 a (measured 0.1–0.3 %; the edge nodes carry the zone's end).
    for (x, _, _, p) in &list {
        if x.abs() < 0.9 * a {
            let hertz = p0 * (1.0 - x * x / (a * a)).sqrt();
            assert!(
                (p - hertz).abs() < 0.01 * p0,
                "x = {x}: p = {p}, Hertz {hertz}"
            );
        }
    }
    // Every node inside the stick zone's bound carries |q| ≤ μp, and the slipping ones μp.
    for (x, state, q, p) in &list {
        if state == "slip" {
            assert!(
                (q.abs() - MU * p).abs() < 1e-6 * MU * p0,
                "x = {x}: q = {q}, μp = {}",
                MU * p
            );
        }
        assert!(q.abs() <= MU * p * (1.0 + 1e-6) + 1e-12 * p0, "x = {x}");
    }
}

/// The stick half-width on the side `side` (±1) of x = 0: half-way between the outermost
/// sticking node and the innermost slipping one (asserting that no node slips inside).
fn stick_half_width(list: &[(f64, String, f64, f64)], side: f64) -> f64 {
    let half: Vec<&(f64, String, f64, f64)> = list.iter().filter(|n| n.0 * side >= 0.0).collect();
    let stick = half
        .iter()
        .filter(|n| n.1 == "stick")
        .map(|n| n.0.abs())
        .fold(0.0, f64::max);
    let slip = half
        .iter()
        .filter(|n| n.1 == "slip")
        .map(|n| n.0.abs())
        .fold(f64::INFINITY, f64::min);
    assert!(
        slip > stick,
        "side {side}: slip inside the stick zone: {list:?}"
    );
    0.5 * (stick + slip)
}

/// The rms of |q| against Cattaneo's over the nodes with |x| < a (unweighted), with a, p₀ and c
/// from the pair's own P and Q for the relative radius `r_star`; also c / a.
fn traction_rms(pair: &Value, r_star: f64) -> (f64, f64) {
    let (a, p0, c) = theory_for(pair, r_star);
    let (mut err, mut norm) = (0.0, 0.0);
    for (x, _, q, _) in nodes(pair).iter().filter(|n| n.0.abs() < a) {
        let want = cattaneo(*x, a, p0, c);
        err += (q.abs() - want).powi(2);
        norm += want * want;
    }
    ((err / norm).sqrt(), c / a)
}

/// The mirror scene of `mirror/mod.rs` with cylinders of radius `radius` (R* = R/2), zone h and
/// arc spacing 0.00133 (a/25 for a ≈ 0.0333), pressed by `press` and then shifted by `shift` in
/// two increments (mortar, Coulomb μ), solved with the default backend; result.json.
fn mirror_run(radius: f64, press: f64, shift: f64) -> Value {
    let dir = tempfile::tempdir().unwrap();
    let params = mirror::Params {
        radius,
        hmax: 0.016,
        zone: 0.05,
        zone_hmax: 0.00133,
        arc: 0.00133,
        press,
        shift,
        increments: 2,
        mu: MU,
        formulation: "mortar",
    };
    let (text, _) = mirror::write_scene(&params, dir.path());
    std::fs::write(dir.path().join("scene.toml"), text).unwrap();
    succeeded(&signorini(
        &["solve", "scene.toml", "--out", "out"],
        dir.path(),
    ));
    json(&dir.path().join("out/result.json"))
}

// Two equal cylinders, R = 20 each (R* = 10), mirror images about the contact line with exactly
// mirrored meshes, built at test time (tests/mirror/mod.rs: the lower slab meshed by the
// library's mesher, the upper its reflection): equal bodies mirrored about the contact line
// decouple the normal and tangential problems by symmetry, as Cattaneo's half-spaces do (the
// cylinder on a block of `scene` does not: the press alone locks in 1.7 % of μp₀, odd in x, and
// that scene's rms stays at 3.6–3.9 %).  Zone h = a/25 with the arc's polygon spacing equal to
// it; a ≈ 0.0333, Q/(μP) ≈ 0.52.  Measured 1.61 % (even 1.50 %, odd 0.57 %) with the rows along
// the mean of the two sides' normals; 1.87 % along the slave's normals, tilted by x/R, which
// mixed p·x/R into q (BENCHMARKS.md, Cattaneo; the error sits on the nodes next to the cusps
// ±c, where q's slope is infinite); the bound, 3 %, is the issue's.  56 k DOFs; 9 s in release (mesh, write, solve) on the 2-core machine at load 9.
#[test]
fn pressed_then_shifted_the_tangential_traction_follows_cattaneo_within_3_percent_rms() {
    let radius = 20.0;
    let r = mirror_run(radius, 0.000215, 0.00005);
    assert_eq!(r["status"], "solved", "{}", r["message"]);
    let pair = &r["contacts"][0];
    let (a, _, _) = theory_for(pair, radius / 2.0);
    // The case must be partial slip with a resolved zone, or the bound says nothing: a stick
    // zone well inside the contact (Q/(μP) ≈ 0.52 here) and ≥ 40 nodes across 2a.
    let (rms, c_over_a) = traction_rms(pair, radius / 2.0);
    assert!(c_over_a > 0.4 && c_over_a < 0.9, "c/a = {c_over_a}");
    let across = nodes(pair).iter().filter(|n| n.0.abs() < a).count();
    assert!(across >= 40, "{across} nodes across the contact");
    let (even, odd) = parity_split(pair, radius / 2.0);
    eprintln!("q rms {rms:.4}: even {even:.4}, odd {odd:.4} of Cattaneo's rms");
    assert!(rms < 0.03, "rms {rms}");
    // The stick half-width within the issue's 2 % on both sides (Cattaneo's c from the pair's
    // own P and Q; the zone's node spacing a/25 = 0.058 c resolves it to ±2.9 % by a node's
    // position, the midpoint between the last sticking and first slipping node to about half).
    let (_, _, c) = theory_for(pair, radius / 2.0);
    let list = nodes(pair);
    for side in [-1.0, 1.0] {
        let measured = stick_half_width(&list, side);
        assert!(
            (measured - c).abs() < 0.02 * c,
            "side {side}: c = {measured}, Cattaneo {c}"
        );
    }
}

/// The odd part in x of |q| on the nodes with |x| < a: (|q(x)| − |q(−x)|) / 2, |q(−x)|
/// interpolated linearly between the nodes beside −x; as (x, odd part).
fn odd_part(list: &[(f64, String, f64, f64)], a: f64) -> Vec<(f64, f64)> {
    let at = |x: f64| -> f64 {
        let k = list.partition_point(|n| n.0 < x).clamp(1, list.len() - 1);
        let (l, r) = (&list[k - 1], &list[k]);
        let s = (x - l.0) / (r.0 - l.0);
        (1.0 - s) * l.2.abs() + s * r.2.abs()
    };
    list.iter()
        .filter(|n| n.0.abs() < a)
        .map(|n| (n.0, 0.5 * (n.2.abs() - at(-n.0))))
        .collect()
}

/// The error of |q| against Cattaneo's over the nodes with |x| < a, split by parity in x:
/// (even, odd) rms, each relative to Cattaneo's rms (the even part (|q(x)| + |q(−x)|)/2 − q_C).
fn parity_split(pair: &Value, r_star: f64) -> (f64, f64) {
    let (a, p0, c) = theory_for(pair, r_star);
    let list = nodes(pair);
    let inner = list.iter().filter(|n| n.0.abs() < a);
    let (mut odd2, mut even2, mut norm2) = (0.0, 0.0, 0.0);
    for ((x, o), n) in odd_part(&list, a).iter().zip(inner) {
        let want = cattaneo(*x, a, p0, c);
        let even = n.2.abs() - o - want;
        odd2 += o * o;
        even2 += even * even;
        norm2 += want * want;
    }
    ((even2 / norm2).sqrt(), (odd2 / norm2).sqrt())
}

// Two equal cylinders mirrored about the contact line (R = 10 each, zone h = a/25, Q/(μP) ≈ 0.52):
// Cattaneo's q is even in x, so the odd part of the computed |q| is error only.  Some comes from
// the mesh, which is mirrored about the contact line but not about x = 0 (the node positions at
// ±x differ; |q(−x)| is interpolated across the cusps at ±c, where q's slope is infinite): that
// part of the error has no preferred parity, so it is bounded by the even part of the same
// error (the even part is the mesh's error alone: q's theory is even).  Rows along tilted
// normals add an odd part that no mesh removes: along the slave's normals (before) the odd
// part was 2.2 % rms of Cattaneo's q against an even part of 1.5 % (BENCHMARKS.md, Cattaneo,
// R = 10, a/25).  So: odd rms ≤ even rms, both measured on the same run.  ≈ 55 k DOFs, 15 s.
// Frictional mortar rows act along the compliance-weighted mean of the two sides' normals
// (docs/scene.md), the flat interface's normal here: measured odd 1.12 %, even 1.47 %
// (BENCHMARKS.md, Cattaneo: "interface frame").  Along the slave's normals it failed (2.22 %).
#[test]
fn on_mirror_image_cylinders_the_tangential_traction_is_even_in_x() {
    let radius = 10.0;
    let r = mirror_run(radius, 0.00043, 0.0001);
    assert_eq!(r["status"], "solved", "{}", r["message"]);
    let pair = &r["contacts"][0];
    let (a, _, c) = theory_for(pair, radius / 2.0);
    assert!(c > 0.4 * a && c < 0.9 * a, "c/a = {}", c / a);
    let (even, odd) = parity_split(pair, radius / 2.0);
    let (rms, _) = traction_rms(pair, radius / 2.0);
    eprintln!("q rms {rms:.4}: even {even:.4}, odd {odd:.4} of Cattaneo's rms");
    assert!(
        odd <= even,
        "odd part {odd}, even part {even} of Cattaneo's rms"
    );
}

/// Proportional loading (press and shift together, Q/P = const < μ): Cattaneo's continuous path
/// never slips.  The path is discretised in increments, and a node that closes inside an
/// increment sticks where the increment's start left it, open — a slip the continuous path
/// does not have, shrinking with the increments: measured on this scene 2 slipping nodes with 8
/// increments (6 with 2; issue 20 once took them for a finite-body coupling), none with 16.
#[test]
fn proportional_loading_below_mu_gives_no_slip_at_all() {
    let r = run(&scene(
        "[[step]]\nloads = { press = 1.0, shift = 1.0 }\nincrements = 16",
    ));
    assert_eq!(r["status"], "solved");
    let list = nodes(&r["contacts"][0]);
    assert!(list.iter().all(|n| n.1 != "slip"), "{list:?}");
}

#[test]
fn a_coulomb_run_whose_bounds_repeat_stops_at_once() {
    // Found on this scene: dual-ssn's inner solves settled `inaccurate` with Coulomb bounds that
    // reproduced themselves exactly (its zero-bound rows were taken for one-sided rows, since
    // fixed: crates/dual/tests/box_rows.rs), and the fixed point repeated the same solve until
    // the time limit (36 outer iterations in 20 s).  Whatever dual-ssn's inner verdict, the run
    // must end in a few outer iterations per increment, never at the time limit.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.toml"), scene(PRESS_THEN_SHIFT)).unwrap();
    let o = signorini(
        &[
            "solve",
            "scene.toml",
            "--backend",
            "dual-ssn",
            "--time-limit",
            "60",
            "--out",
            "out",
        ],
        dir.path(),
    );
    let r = json(&dir.path().join("out/result.json"));
    assert_ne!(r["status"], "time-limit", "exit {:?}", o.status);
    for step in r["steps"].as_array().unwrap() {
        let outer = step["outer_iterations"].as_u64().unwrap();
        assert!(outer <= 12, "{step}");
    }
}

/// Solves `scene` with `backend` and `--coulomb method` at tol 1e-10; returns result.json.
fn run_with(scene: &str, backend: &str, method: &str) -> Value {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.toml"), scene).unwrap();
    succeeded(&signorini(
        &[
            "solve",
            "scene.toml",
            "--backend",
            backend,
            "--coulomb",
            method,
            "--tol",
            "1e-10",
            "--out",
            "out",
        ],
        dir.path(),
    ));
    json(&dir.path().join("out/result.json"))
}

#[test]
fn coulomb_by_semismooth_newton_and_by_the_fixed_point_agree() {
    // Two different methods for the same conditions (pdas's Newton with λₜ = ±μλₙ inside its
    // active sets; the fixed point over Tresca problems, through pdas and through dual-ssn, two
    // direct methods) on the partial-slip path, where the answer is unique for μ = 0.3 (the
    // fixed point's map contracts): every node's state and tractions must agree.  Measured:
    // dual-ssn and pdas agree to 1e-12 of the largest traction; 1e-7 of p₀ leaves room.  (Not
    // dual-pgs: at the same --tol its stick tractions differ by 1.3e-7 p₀ — the residuals'
    // force scale here is the lifting of the prescribed displacement, far above the contact
    // forces, so --tol does not bound a stick node's λₜ that tightly.)
    let scene = scene(PRESS_THEN_SHIFT);
    let newton = run_with(&scene, "pdas", "newton");
    assert_eq!(newton["coulomb"]["method"], "newton");
    assert!(newton["coulomb"]["converged"].as_bool().unwrap());
    let reference = nodes(&newton["contacts"][0]);
    let p0 = theory(&newton["contacts"][0]).1;
    for backend in ["pdas", "dual-ssn"] {
        let fixed = run_with(&scene, backend, "fixed-point");
        assert_eq!(fixed["coulomb"]["method"], "fixed-point", "{backend}");
        let other = nodes(&fixed["contacts"][0]);
        assert_eq!(other.len(), reference.len(), "{backend}");
        for (a, b) in reference.iter().zip(&other) {
            assert_eq!(a.1, b.1, "{backend}: state at x = {}", a.0);
            assert!(
                (a.2 - b.2).abs() < 1e-7 * p0,
                "{backend}: q at x = {}: {a:?} {b:?}",
                a.0
            );
            assert!(
                (a.3 - b.3).abs() < 1e-7 * p0,
                "{backend}: p at x = {}: {a:?} {b:?}",
                a.0
            );
        }
    }
}

/// result.json of the Cattaneo path (`scene(PRESS_THEN_SHIFT)`) solved with `backend` at the
/// default tolerance, 60 s at most.
fn solve_path(backend: &str) -> Value {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.toml"), scene(PRESS_THEN_SHIFT)).unwrap();
    succeeded(&signorini(
        &[
            "solve",
            "scene.toml",
            "--backend",
            backend,
            "--time-limit",
            "60",
            "--out",
            "out",
        ],
        dir.path(),
    ));
    json(&dir.path().join("out/result.json"))
}

// dual-ssn on this path: every inner Tresca solve has zero-bound tangential rows (no normal
// force, bound μ·0), which dual-ssn once took for one-sided rows — the run ended `inaccurate`
// with |λt| up to 4.7e-4 beyond the bound 0.  Now it must solve the path and agree with pdas, an
// independent method (primal active set on the whole system, no condensed dual).
#[test]
fn dual_ssn_solves_the_cattaneo_path_and_agrees_with_pdas() {
    let ssn = solve_path("dual-ssn");
    let pdas = solve_path("pdas");
    for r in [&ssn, &pdas] {
        assert_eq!(r["status"], "solved", "{}: {}", r["backend"], r["message"]);
        for step in r["steps"].as_array().unwrap() {
            assert_eq!(step["status"], "solved", "{}: {step}", r["backend"]);
        }
    }
    // 1e-6 relative: both answers meet the KKT tolerance 1e-9 (result.json's `tolerance`); a
    // thousandfold margin covers the conditioning of the stick zone's tangential problem.
    // (Measured: 3e-13 on the forces, 1.3e-12 of max |q| per node.)
    let (a, b) = (&ssn["contacts"][0], &pdas["contacts"][0]);
    for key in ["normal_force", "tangential_force"] {
        let (x, y) = (a[key].as_f64().unwrap(), b[key].as_f64().unwrap());
        assert!(
            (x - y).abs() <= 1e-6 * y.abs(),
            "{key}: dual-ssn {x}, pdas {y}"
        );
    }
    // The shift is resisted: Q = |tangential force| is a sizeable fraction of μP (Cattaneo: the
    // stick zone c = a √(1 − Q/(μP)) is inside the contact), not the ~0 of a wrong answer.
    let q = b["tangential_force"].as_f64().unwrap().abs();
    let p = b["normal_force"].as_f64().unwrap();
    assert!(
        q > 0.1 * 0.3 * p && q < 0.3 * p,
        "Q = {q}, μP = {}",
        0.3 * p
    );
    // Node by node: the same stick/slip states and tangential tractions to 1e-6 of the largest.
    let nodes = |pair: &Value| -> Vec<(String, f64)> {
        pair["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| {
                (
                    n["state"].as_str().unwrap().to_string(),
                    n["tangential_traction"].as_f64().unwrap(),
                )
            })
            .collect()
    };
    let (na, nb) = (nodes(a), nodes(b));
    assert_eq!(na.len(), nb.len());
    let scale = nb.iter().map(|n| n.1.abs()).fold(0.0, f64::max);
    for (i, (x, y)) in na.iter().zip(&nb).enumerate() {
        assert_eq!(x.0, y.0, "node {i}: dual-ssn {x:?}, pdas {y:?}");
        assert!(
            (x.1 - y.1).abs() <= 1e-6 * scale,
            "node {i}: dual-ssn {x:?}, pdas {y:?}"
        );
    }
}
