//! The properties of a `solved` answer that statics and the friction law fix, judged from the
//! scene, the model's rows and the answer's multipliers — never from the solver's own account of
//! its accuracy:
//!
//! * **solved-floating-statics**: a body with no `[[dirichlet]]` (held by contact alone) is in
//!   equilibrium: its applied load (result.json `bodies[].applied`) plus the contact forces the
//!   multipliers put on it (−Bᵀλ summed over its DOFs, from B and λ) is zero; when it is in one
//!   pair whose rows share one normal n (a flat interface), the pair's reported scalars balance
//!   it too: applied + σ (N n + T t) = 0 with N = `normal_force`, T = `tangential_force`,
//!   t = (n_y, −n_x), σ = +1 when the body is the slave and −1 when it is the master.
//! * **solved-friction-law**: at every node of a frictional pair, |`tangential_traction`| ≤
//!   μ · max(0, `pressure`) (Coulomb) or ≤ s (Tresca).
//! * **overdrag-not-solved**: a floating body in one frictional pair whose load exceeds what the
//!   pair can carry — whatever the multipliers — is never `solved` (it must end
//!   `dual-infeasible` or another non-solved status).  Each row's force on the body is
//!   σ(λ n + λₜ t) with λ ≥ 0; with every σn within θ of their mean direction m and
//!   φ = atan μ, each lies in the cone of half-angle φ + θ about m (Coulomb), so their sum does:
//!   the load's component along −m, N, and across it, T, satisfy |T| ≤ N tan(φ + θ).  Tresca:
//!   |λₜ| ≤ s w each, S = s Σw, so N ≥ −S and |T| ≤ (N + S) tan θ + S.
//!
//! **The slack, from the tolerance** (docs/scene.md, Residuals): `solved` means stationarity
//! |(A x − f + Bᵀλ)ⱼ| ≤ tol · F̃ⱼ at every DOF j and, for a box row, |λᵢ| − sᵢ ≤ tol · F̃ᵢ, where
//! the force scales F̃ are at most the component's F_c = max(‖f_c‖∞, k̄_c G_c) (the QP is
//! scaled by scalars, so the ratios hold in the scene's units).  Without initial overlap
//! (G_c = 0; scenes with one are not judged here) F̃ ≤ F = ‖f‖∞ over the free DOFs of the bodies
//! joined to the body by pairs — the QP's load: the nodal loads minus the lifting −K u_d of the
//! prescribed values.  A floating body's stiffness rows sum to zero along a rigid translation, so
//! summing its n nodes' stationarity in x (or y) leaves applied + contact, off by at most
//! n · tol · F, plus the round-off of that cancellation, ε-sized against internal forces that
//! nearly incompressible bodies amplify by κ = (1 − ν)/(1 − 2ν): 1e-13 · κ · n · F.  A node's
//! law is off by at most tol · F (as a traction, / its weight).  Each is doubled for the
//! round-off of scaling back to the scene's units.

// `!(x <= bound)` on purpose: a NaN fails the check.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::collections::BTreeMap;
use std::sync::Mutex;

use signorini::run::Outcome;
use signorini_core::scene::{Friction, Scene};

use super::props::Finding;

type V = [f64; 2];

fn push(found: &mut Vec<Finding>, property: &'static str, detail: String) {
    found.push(Finding { property, detail });
}

/// The bodies joined to body `b` by pairs that have rows (b included).
fn joined(outcome: &Outcome, b: usize) -> Vec<usize> {
    let mut set = vec![b];
    let mut grew = true;
    while grew {
        grew = false;
        for pair in outcome.model.contacts.iter().filter(|p| !p.rows.is_empty()) {
            for (x, y) in [(pair.slave, pair.master), (pair.master, pair.slave)] {
                if set.contains(&x) && !set.contains(&y) {
                    set.push(y);
                    grew = true;
                }
            }
        }
    }
    set
}

/// F of the module's slack: the largest |QP load| over the free DOFs of `bodies`.
fn load_scale(outcome: &Outcome, bodies: &[usize]) -> f64 {
    let m = &outcome.model;
    let mut f = m.load.clone();
    for (v, (row, col)) in m.supports.iter() {
        let ud = m
            .fixed_dofs
            .get(col)
            .and_then(|&d| m.fixed[d])
            .unwrap_or(0.0);
        f[row] -= v * ud;
    }
    bodies
        .iter()
        .flat_map(|&b| m.dofs.body_range(b))
        .filter(|&j| m.fixed[j].is_none())
        .map(|j| f[j].abs())
        .fold(0.0, f64::max)
}

/// The body's rows in a pair, as (σ n, Σ master weights) per row, and whether the body is slave.
fn rows_on(outcome: &Outcome, pair: usize, b: usize) -> Option<(Vec<(V, f64)>, f64)> {
    let rows = outcome.model.contacts.iter().find(|p| p.pair == pair)?;
    let sigma = if rows.slave == b {
        1.0
    } else if rows.master == b {
        -1.0
    } else {
        return None;
    };
    let list = rows
        .rows
        .iter()
        .map(|r| {
            let w: f64 = r.masters.iter().map(|&(_, w)| w).sum();
            ([sigma * r.normal[0], sigma * r.normal[1]], w)
        })
        .collect();
    Some((list, sigma))
}

/// What the survey reports of the frictional cases: counts by label (`fuzz_survey` prints them).
static TALLY: Mutex<BTreeMap<String, usize>> = Mutex::new(BTreeMap::new());

fn count(label: String) {
    if let Ok(mut t) = TALLY.lock() {
        *t.entry(label).or_default() += 1;
    }
}

/// Counts a frictional scene refused by parsing (`broken`: a mutation broke it).
pub fn refused(toml: &str, broken: bool) {
    if toml.contains("\nfriction = ") || toml.contains("\ntresca = ") {
        count(format!(
            "frictional refused by parsing ({})",
            if broken { "broken" } else { "unbroken" }
        ));
    }
}

/// The counts so far, by label.
pub fn tally() -> BTreeMap<String, usize> {
    TALLY.lock().map(|t| t.clone()).unwrap_or_default()
}

/// Checks the module's properties on an answer that ran: statics and the law when it is
/// `solved`, the capacity on every one (tallied by status; a failure only when `solved`).
pub fn check(scene: &Scene, outcome: &Outcome, tol: f64, found: &mut Vec<Finding>) {
    let m = &outcome.model;
    let status = outcome.report.status.as_str();
    let solved = status == "solved";
    if let Some(law) = scene.contacts.iter().find_map(|c| c.friction) {
        let law = match law {
            Friction::Coulomb(_) => "coulomb",
            Friction::Tresca(_) => "tresca",
        };
        count(format!("frictional ({law}) ran: {status}"));
    }
    let n_normal = m.gap.len().saturating_sub(m.tangential.len());
    // An initial overlap's force scale k̄ G is not in the outputs: such scenes are not judged.
    if m.gap[..n_normal].iter().any(|g| *g < 0.0) {
        return;
    }
    let report = &outcome.report;
    let lambda = &outcome.solution.multipliers;
    let mut bt = vec![0.0; m.load.len()];
    for (v, (i, j)) in m.constraints.iter() {
        bt[j] += v * lambda.get(i).copied().unwrap_or(f64::NAN);
    }
    if solved {
        check_law(scene, outcome, tol, found);
    }
    for b in 0..scene.bodies.len() {
        if scene.dirichlet.iter().any(|d| d.body == b) {
            continue;
        }
        let pairs: Vec<usize> = (0..scene.contacts.len())
            .filter(|&p| scene.contacts[p].bodies.contains(&b))
            .filter(|&p| m.contacts.iter().any(|r| r.pair == p && !r.rows.is_empty()))
            .collect();
        let Some(body) = report.bodies.get(b) else {
            continue;
        };
        if pairs.is_empty() {
            continue;
        }
        let force = load_scale(outcome, &joined(outcome, b));
        if !(force > 0.0 && force.is_finite()) {
            continue;
        }
        let nodes = m.meshes[b].nodes.len() as f64;
        let nu = scene.bodies[b].poisson;
        let kappa = ((1.0 - nu) / (1.0 - 2.0 * nu)).abs().max(1.0);
        let slack = 2.0 * (nodes * tol * force + 1e-13 * kappa * nodes * force);
        let applied = body.applied;
        let load: V = [applied[0] + body.reaction[0], applied[1] + body.reaction[1]];
        let mut contact = [0.0; 2];
        for j in m.dofs.body_range(b) {
            contact[j % 2] -= bt[j];
        }
        if solved {
            count("floating body judged by statics".into());
        }
        for c in 0..2 {
            if !solved {
                break;
            }
            let miss = load[c] + contact[c];
            if !(miss.abs() <= slack + 1e-12 * applied[c].abs()) {
                push(
                    found,
                    "solved-floating-statics",
                    format!(
                        "body {:?} (no support): applied {:?} + contact forces from the \
                         multipliers {contact:?} leave {miss:e} in {} (allowed {slack:.1e})",
                        scene.bodies[b].name,
                        applied,
                        ["x", "y"][c],
                    ),
                );
                return;
            }
        }
        let [pair] = pairs[..] else { continue };
        let Some((rows, sigma)) = rows_on(outcome, pair, b) else {
            continue;
        };
        // Master weights that do not sum to one spread a row's force unevenly: not judged.
        if sigma < 0.0 && rows.iter().any(|(_, w)| (w - 1.0).abs() > 1e-9) {
            continue;
        }
        if solved {
            check_scalars(scene, outcome, pair, b, &rows, sigma, load, slack, found);
        }
        check_overdrag(
            scene,
            outcome,
            pair,
            b,
            &rows,
            load,
            slack,
            tol * force,
            found,
        );
    }
}

/// The pair's reported `normal_force` and `tangential_force` balance the floating body's load
/// when its rows share one normal.
#[allow(clippy::too_many_arguments)]
fn check_scalars(
    scene: &Scene,
    outcome: &Outcome,
    pair: usize,
    b: usize,
    rows: &[(V, f64)],
    sigma: f64,
    load: V,
    slack: f64,
    found: &mut Vec<Finding>,
) {
    let n0 = rows[0].0;
    if rows
        .iter()
        .any(|(n, _)| (n[0] - n0[0]).abs() > 1e-12 || (n[1] - n0[1]).abs() > 1e-12)
    {
        return;
    }
    let Some(rep) = outcome.report.contacts.get(pair) else {
        return;
    };
    let names = scene.contacts[pair]
        .bodies
        .map(|i| scene.bodies[i].name.clone());
    if rep.bodies != names {
        return;
    }
    // σ n is the row's normal as seen by the body; the normal of the pair itself is n.
    let n = [sigma * n0[0], sigma * n0[1]];
    let t = [n[1], -n[0]];
    let (nf, tf) = (rep.normal_force, rep.tangential_force.unwrap_or(0.0));
    let on_body = [
        sigma * (nf * n[0] + tf * t[0]),
        sigma * (nf * n[1] + tf * t[1]),
    ];
    for c in 0..2 {
        let miss = load[c] + on_body[c];
        if !(miss.abs() <= slack + 1e-12 * load[c].abs()) {
            push(
                found,
                "solved-floating-statics",
                format!(
                    "body {:?} (no support), contact #{}: applied {load:?} against \
                     normal_force {nf:e} and tangential_force {tf:e} along n = {n:?} leaves \
                     {miss:e} in {} (allowed {slack:.1e})",
                    scene.bodies[b].name,
                    pair + 1,
                    ["x", "y"][c],
                ),
            );
            return;
        }
    }
}

/// A floating body whose load exceeds its one frictional pair's capacity is not `solved`.
#[allow(clippy::too_many_arguments)]
fn check_overdrag(
    scene: &Scene,
    outcome: &Outcome,
    pair: usize,
    b: usize,
    rows: &[(V, f64)],
    load: V,
    slack: f64,
    row_slack: f64,
    found: &mut Vec<Finding>,
) {
    let Some(law) = scene.contacts[pair].friction else {
        return;
    };
    let sum = rows
        .iter()
        .fold([0.0, 0.0], |s, (n, _)| [s[0] + n[0], s[1] + n[1]]);
    let len = sum[0].hypot(sum[1]);
    if !(len > 0.0) {
        return;
    }
    let mdir = [sum[0] / len, sum[1] / len];
    let theta = rows
        .iter()
        .map(|(n, _)| (n[0] * mdir[0] + n[1] * mdir[1]).clamp(-1.0, 1.0).acos())
        .fold(0.0, f64::max);
    // What contact must supply, −load, along m (N) and across it (T).
    let need = [-load[0], -load[1]];
    let normal = need[0] * mdir[0] + need[1] * mdir[1];
    let across = (need[0] * mdir[1] - need[1] * mdir[0]).abs();
    let n_rows = rows.len() as f64;
    let (limit, floor, turn, what) = match law {
        Friction::Coulomb(mu) => {
            let cone = mu.atan() + theta;
            if cone >= 89f64.to_radians() {
                return;
            }
            (
                normal.max(0.0) * cone.tan(),
                0.0,
                cone.tan(),
                format!("Coulomb μ = {mu}: N tan(atan μ + θ)"),
            )
        }
        Friction::Tresca(s) => {
            if theta >= 89f64.to_radians() {
                return;
            }
            let Some(pr) = outcome.model.contacts.iter().find(|p| p.pair == pair) else {
                return;
            };
            let cap = s * pr.rows.iter().map(|r| r.tributary).sum::<f64>();
            (
                (normal + cap).max(0.0) * theta.tan() + cap,
                -cap,
                1.0 + theta.tan(),
                format!("Tresca s = {s}: (N + S) tan θ + S, S = {cap:e}"),
            )
        }
    };
    // Ten times what the answer's own errors could add: the statics slack in each direction
    // and every row's law slack, each turned by the cone.
    let allowance = 10.0 * (slack + n_rows * row_slack) * (1.0 + turn);
    let status = outcome.report.status.as_str();
    let beyond = normal < floor - allowance || across > limit + allowance;
    let kind = if matches!(law, Friction::Coulomb(_)) {
        "coulomb"
    } else {
        "tresca"
    };
    count(format!(
        "floating in one {kind} pair, load {} capacity: {status}",
        if beyond { "beyond" } else { "within" }
    ));
    if beyond && status == "solved" {
        push(
            found,
            "overdrag-not-solved",
            format!(
                "body {:?} (no support), contact #{}: load {load:?} needs N = {normal:e} along \
                 the rows' mean normal and T = {across:e} across it, beyond the capacity \
                 {limit:e} ({what}, θ = {:.3} rad), yet status solved",
                scene.bodies[b].name,
                pair + 1,
                theta
            ),
        );
    }
}

/// Every node of a frictional pair keeps its tangential traction within the law's bound.
fn check_law(scene: &Scene, outcome: &Outcome, tol: f64, found: &mut Vec<Finding>) {
    for (p, rep) in outcome.report.contacts.iter().enumerate() {
        let Some(pair) = scene.contacts.get(p) else {
            continue;
        };
        let Some(law) = pair.friction else { continue };
        let force = load_scale(outcome, &joined(outcome, pair.bodies[0]));
        for node in &rep.nodes {
            let (Some(q), w) = (node.tangential_traction, node.weight) else {
                continue;
            };
            if !(w > 0.0) {
                continue;
            }
            let bound = match law {
                Friction::Coulomb(mu) => mu * node.pressure.max(0.0),
                Friction::Tresca(s) => s,
            };
            let slack = 2.0 * tol * force / w;
            if !(q.abs() <= bound + slack) {
                push(
                    found,
                    "solved-friction-law",
                    format!(
                        "contact #{} node ({:e}, {:e}): |tangential_traction| {:e} > bound {bound:e} \
                         ({law:?}, pressure {:e}) + slack {slack:.1e}",
                        p + 1,
                        node.x,
                        node.y,
                        q.abs(),
                        node.pressure
                    ),
                );
                return;
            }
        }
    }
}
