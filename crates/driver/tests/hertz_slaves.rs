//! Issue 21 (accuracy): mortar on a curved slave.  The Hertz cylinder of
//! `fixtures/accuracy/hertz-graded.toml` (R = 1, a = 0.05, refine boxes hmax 0.002), with its arc
//! polygon as fine as the refine box (vertices every 0.002: a boundary finer than its own
//! elements makes the nodal reactions alternate by ±2.5 % node to node, with either
//! formulation — BENCHMARKS.md, "Hertz: mortar on a curved slave"), solved with mortar with
//! either body as slave, on equal bodies and on a block 1000 times stiffer than the cylinder.
//! Measures, against Johnson's formulas for the run's own load: the largest nodal pressure and
//! the rms of the nodal pressure error over the nodes within a of the centre (both relative to
//! p₀), and the half-width from the second moment of the forces.  The pair's `force` (the
//! resultant vector) must equal the slave's contact force.

#![allow(clippy::unwrap_used)]

mod common;

use signorini::auto::AutoBackend;
use signorini::run;
use signorini_core::mesh::MeshLimits;
use signorini_core::qp::{QpStatus, SolveOptions};
use signorini_core::scene::Scene;

const R: f64 = 1.0;
const A: f64 = 0.05;
const NU: f64 = 0.3;

/// E* of a cylinder of E = 1 on a block of E = `block` (both ν = 0.3).
fn e_star(block: f64) -> f64 {
    1.0 / ((1.0 - NU * NU) + (1.0 - NU * NU) / block)
}

fn scene(block: f64, slave: &str) -> String {
    let pts = common::hertz_cap_polygon(0.002);
    let (xl, xr) = (pts[0][0], pts[pts.len() - 1][0]);
    let load = std::f64::consts::PI * A * A * e_star(block) / (4.0 * R);
    let poly: Vec<String> = pts
        .iter()
        .map(|p| format!("[{}, {}]", p[0], p[1]))
        .collect();
    format!(
        r#"
[[body]]
name = "cap"
polygon = [{poly}]
hmax = 0.016
young = 1.0
poisson = 0.3
[[body.refine]]
region = [0.7, 0.9, 0.8, 0.9]
hmax = 0.002

[[body]]
name = "block"
polygon = [[0.0, 0.0], [1.6, 0.0], [1.6, 0.8], [0.0, 0.8]]
hmax = 0.016
young = {block:?}
poisson = 0.3
[[body.refine]]
region = [0.7, 0.9, 0.7, 0.8]
hmax = 0.002

[[dirichlet]]
body = "block"
region = [0.0, 1.6, 0.0, 0.0]

[[dirichlet]]
body = "cap"
region = [{xl}, {xr}, 1.4, 1.4]
components = ["x"]

[[neumann]]
body = "cap"
region = [{xl}, {xr}, 1.4, 1.4]
traction = [0.0, {t:?}]

[[contact]]
bodies = ["cap", "block"]
region = [0.6, 1.0, 0.79, 0.83]
slave = "{slave}"
formulation = "mortar"
"#,
        poly = poly.join(", "),
        t = -load / (xr - xl),
    )
}

/// (largest nodal pressure / p₀ − 1, rms profile error / p₀, moment half-width / a − 1).
fn errors(block: f64, slave: &str) -> (f64, f64, f64) {
    let s = Scene::from_toml(&scene(block, slave)).unwrap();
    let mut backend = AutoBackend::default();
    let o = run::solve_scene(
        &s,
        &mut backend,
        &SolveOptions::default(),
        &MeshLimits::default(),
    )
    .unwrap();
    assert_eq!(o.solution.status, QpStatus::Solved);
    let cap = o.report.bodies.iter().find(|b| b.name == "cap").unwrap();
    let load = -cap.applied[1];
    let a = (4.0 * load * R / (std::f64::consts::PI * e_star(block))).sqrt();
    let p0 = 2.0 * load / (std::f64::consts::PI * a);
    let pair = &o.report.contacts[0];
    // The resultant equals the slave's contact force (one pair: Bᵀλ on the slave's DOFs), to
    // the solver's tolerance (1e-9 relative) times the few hundred rows.
    let body = o.report.bodies.iter().find(|b| b.name == slave).unwrap();
    for k in 0..2 {
        assert!(
            (pair.force[k] - body.contact_force[k]).abs() <= 1e-7 * load,
            "{:?} vs {:?}",
            pair.force,
            body.contact_force
        );
    }
    let (mut sq, mut n, mut f, mut m) = (0.0, 0, 0.0, 0.0);
    let mut pmax = 0.0_f64;
    for node in &pair.nodes {
        let d = (node.x - 0.8).hypot(node.y - 0.8);
        let l = node.multiplier.max(0.0);
        f += l;
        m += l * d * d;
        if node.active {
            pmax = pmax.max(node.pressure);
        }
        if d < a {
            let exact = p0 * (1.0 - d * d / (a * a)).sqrt();
            let p = if node.active { node.pressure } else { 0.0 };
            sq += (p - exact).powi(2);
            n += 1;
        }
    }
    let e = (
        pmax / p0 - 1.0,
        (sq / n as f64).sqrt() / p0,
        2.0 * (m / f).sqrt() / a - 1.0,
    );
    eprintln!(
        "block E {block}, slave {slave}: max nodal p {:+.3} %, rms {:.3} %, a {:+.3} %",
        100.0 * e.0,
        100.0 * e.1,
        100.0 * e.2
    );
    e
}

/// Equal bodies (Dundurs β = 0: no relative tangential displacement in Hertz's theory, so both
/// slave choices describe the same points).  Budget 1 %: the estimator's bias (h/a)²/3 = 0.05 %,
/// the finite bodies ~0.1 %, the (a/R)² terms 0.25 %, and the discretisation at a/h = 25.
/// Measured after the fix (max, rms, a): cap −0.03 %, 0.21 %, −0.02 %; block +0.20 %, 0.62 %,
/// −0.16 %.
#[test]
fn hertz_mortar_is_within_one_percent_with_either_slave_on_equal_bodies() {
    for slave in ["cap", "block"] {
        let (pmax, rms, a) = errors(1.0, slave);
        assert!(pmax.abs() <= 0.01, "{slave}: max nodal pressure {pmax:e}");
        assert!(rms <= 0.01, "{slave}: profile rms {rms:e}");
        assert!(a.abs() <= 0.01, "{slave}: half-width {a:e}");
    }
}

/// A block 1000 times stiffer than the cylinder, the cylinder as slave: the block is nearly a
/// rigid flat, for which the exact non-penetration condition is vertical at each of the
/// cylinder's material points — Hertz's own condition, so the same 1 % budget holds.  Failed
/// before the rows took the master's normals (rows along the cylinder's tilted normals: max
/// +0.70 %, rms 1.28 %, a −0.70 %); measured after: −0.11 %, 0.22 %, +0.04 %.  With the block
/// as slave the pressure is reported at the block's points, which face cylinder points moved
/// inwards by the cylinder's tangential displacement (1.06 % of a at the edge, measured): a
/// physical shift Hertz neglects (a −0.64 %, rms 1.8 %), see BENCHMARKS.md.
#[test]
fn hertz_mortar_on_a_curved_slave_over_a_stiff_flat_is_within_one_percent() {
    let (pmax, rms, a) = errors(1000.0, "cap");
    assert!(pmax.abs() <= 0.01, "max nodal pressure {pmax:e}");
    assert!(rms <= 0.01, "profile rms {rms:e}");
    assert!(a.abs() <= 0.01, "half-width {a:e}");
}
