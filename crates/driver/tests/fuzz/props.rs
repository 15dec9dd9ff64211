//! The properties every scene must satisfy, checked through the library exactly as the CLI runs
//! a scene: parse, check, solve, write.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use signorini::backends::make_backend;
use signorini::run;
use signorini_core::mesh::MeshLimits;
use signorini_core::qp::{QpStatus, SolveOptions};
use signorini_core::scene::Scene;

use super::gen::Case;

/// A property that failed, with what was seen.
#[derive(Debug, Clone)]
pub struct Finding {
    /// The property's name (see [`PROPERTIES`]).
    pub property: &'static str,
    /// What went wrong.
    pub detail: String,
}

/// Every property, by name.
pub const PROPERTIES: [&str; 12] = [
    // Nothing panics: not parsing, checking, solving nor writing.
    "no-panic",
    // Every stage ends: a case finishes within [`CASE_TIMEOUT`].
    "finishes",
    // The status is one of the documented ones (`QpStatus::as_str`).
    "status-documented",
    // `solved` ⇒ every number in result.json and in the output fields is finite.
    "solved-finite",
    // `solved` ⇒ the residuals meet the tolerance asked for.
    "solved-residuals",
    // `solved` ⇒ no boundary node of a pair's slave body ends up inside the master body
    // (deformed geometry, checked independently of the contact rows).
    "solved-no-interpenetration",
    // Nothing loaded, nothing prescribed, no initial overlap ⇒ a solved answer is at rest.
    "unloaded-at-rest",
    // A refusal names the key or section at fault.
    "refusal-names-key",
    // A refusal writes nothing.
    "refusal-writes-nothing",
    // `check` accepts exactly what `solve` accepts (a solve that runs counts, whatever its status).
    "check-equals-solve",
    // A broken scene (wrong array length, unknown or missing key, NaN, unknown body) is refused.
    "broken-refused",
    // An accepted scene's output files are written and well formed (JSON parses, SVG/VTU are XML).
    "outputs-well-formed",
];

/// The limits used for every case: small, so that a case stays fast and the element guard is hit.
pub fn limits() -> MeshLimits {
    MeshLimits {
        max_elements: 4_000,
        ..MeshLimits::default()
    }
}

/// The solve options: the default tolerance, an iteration cap so no case runs for long.
pub fn options() -> SolveOptions {
    SolveOptions {
        tol: 1e-8,
        max_iter: Some(5_000),
        ..SolveOptions::default()
    }
}

/// Words that locate an error in a scene: its sections and its keys.
const PLACES: [&str; 26] = [
    "body",
    "dirichlet",
    "neumann",
    "contact",
    "probe",
    "model",
    "title",
    "name",
    "polygon",
    "hmax",
    "element",
    "young",
    "poisson",
    "density",
    "region",
    "value",
    "components",
    "traction",
    "points",
    "tx",
    "ty",
    "bodies",
    "slave",
    "point",
    "gravity",
    "thickness",
];

/// A failure's kind: its property and its detail with numbers and temporary paths blanked, so
/// that the survey reports each distinct failure once.
pub fn signature(f: &Finding) -> String {
    let mut out = String::new();
    let mut last_digit = false;
    // The status a broken scene ended with does not make it another kind of failure.
    let detail = f.detail.split("; status").next().unwrap_or("");
    for word in detail.split(' ') {
        let word = if word.contains("/.tmp") {
            word.rsplit('/').next().unwrap_or(word)
        } else {
            word
        };
        for c in word.chars() {
            if c.is_ascii_digit() {
                if !last_digit {
                    out.push('#');
                }
                last_digit = true;
            } else {
                out.push(c);
                last_digit = false;
            }
        }
        out.push(' ');
    }
    let short: String = out.chars().take(90).collect();
    format!("{}: {}", f.property, short.trim_end())
}

/// True when a refusal message names a key: a backticked word, or a section or key name.
pub fn names_a_key(message: &str) -> bool {
    let backticked = message
        .split('`')
        .skip(1)
        .step_by(2)
        .any(|w| !w.is_empty() && w.len() < 40);
    backticked || PLACES.iter().any(|p| message.contains(p))
}

/// Every number in a JSON value is finite and there is no `null` (serde_json writes NaN and ±∞
/// as `null`).  Returns the path of the first offender.
pub fn first_non_finite(v: &serde_json::Value, path: &str) -> Option<String> {
    match v {
        serde_json::Value::Null => Some(format!("{path} = null")),
        serde_json::Value::Number(n) => match n.as_f64() {
            Some(x) if x.is_finite() => None,
            _ => Some(format!("{path} = {n}")),
        },
        serde_json::Value::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(i, x)| first_non_finite(x, &format!("{path}[{i}]"))),
        serde_json::Value::Object(o) => o
            .iter()
            .find_map(|(k, x)| first_non_finite(x, &format!("{path}.{k}"))),
        _ => None,
    }
}

fn dir_is_empty(dir: &Path) -> bool {
    std::fs::read_dir(dir)
        .map(|mut d| d.next().is_none())
        .unwrap_or(true)
}

fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "panic".into())
}

/// Time allowed for one case.  A case has at most [`limits`]' elements per body and an
/// iteration cap, and normally takes milliseconds; 30 s is only there to turn a hang into a
/// finding instead of a stuck test.
pub const CASE_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(30);

/// Runs one scene through parse → check → solve → write and returns every property it breaks.
/// The stages run on a worker thread; one that does not finish within [`CASE_TIMEOUT`] is
/// reported as a `finishes` failure and abandoned (it keeps running until the process exits).
pub fn run_case(case: &Case) -> Vec<Finding> {
    let case = case.clone();
    let (send, receive) = std::sync::mpsc::channel();
    let worker = std::thread::Builder::new()
        .name("fuzz-case".into())
        .spawn(move || {
            let _ = send.send(run_case_here(&case));
        });
    if let Err(e) = worker {
        return vec![Finding {
            property: "finishes",
            detail: format!("cannot start a worker thread: {e}"),
        }];
    }
    match receive.recv_timeout(CASE_TIMEOUT) {
        Ok(found) => found,
        Err(_) => vec![Finding {
            property: "finishes",
            detail: format!("no answer within {} s", CASE_TIMEOUT.as_secs()),
        }],
    }
}

/// [`run_case`] on the calling thread, without a time limit.
pub fn run_case_here(case: &Case) -> Vec<Finding> {
    let mut found = Vec::new();
    let out = match tempfile::tempdir() {
        Ok(d) => d,
        Err(e) => {
            return vec![Finding {
                property: "outputs-well-formed",
                detail: format!("cannot create a temporary directory: {e}"),
            }]
        }
    };
    let target = out.path().join("out");
    let result = catch_unwind(AssertUnwindSafe(|| run_stages(case, &target, &mut found)));
    if let Err(p) = result {
        found.push(Finding {
            property: "no-panic",
            detail: panic_text(&*p),
        });
    }
    found
}

fn fail(found: &mut Vec<Finding>, property: &'static str, detail: String) {
    found.push(Finding { property, detail });
}

fn refused(message: &str, target: &Path, found: &mut Vec<Finding>) {
    if !names_a_key(message) {
        found.push(Finding {
            property: "refusal-names-key",
            detail: message.to_string(),
        });
    }
    if !dir_is_empty(target) {
        found.push(Finding {
            property: "refusal-writes-nothing",
            detail: format!("{} is not empty after: {message}", target.display()),
        });
    }
}

fn run_stages(case: &Case, target: &Path, found: &mut Vec<Finding>) {
    let (toml, must_refuse, backend) = (&case.toml, case.must_refuse.as_deref(), case.backend);
    let scene = match Scene::from_toml(toml) {
        Ok(s) => s,
        Err(e) => {
            refused(&e.to_string(), target, found);
            return;
        }
    };
    let limits = limits();
    let options = options();
    let checked = signorini::check::check(&scene, &limits);
    let mut engine = match make_backend(backend) {
        Ok(b) => b,
        Err(e) => {
            return fail(
                found,
                "status-documented",
                format!("backend {backend}: {e}"),
            )
        }
    };
    let solved = run::solve_scene(&scene, engine.as_mut(), &options, &limits);
    match (&checked, &solved) {
        (Ok(_), Err(e)) => fail(
            found,
            "check-equals-solve",
            format!("check accepted, solve refused: {e}"),
        ),
        (Err(e), Ok(o)) => fail(
            found,
            "check-equals-solve",
            format!(
                "check refused ({e}), solve ran (status {})",
                o.report.status
            ),
        ),
        _ => {}
    }
    if let Err(e) = &checked {
        refused(&e.to_string(), target, found);
    }
    let outcome = match solved {
        Ok(o) => o,
        Err(e) => {
            refused(&e.to_string(), target, found);
            return;
        }
    };
    if let Some(why) = must_refuse {
        found.push(Finding {
            property: "broken-refused",
            detail: format!(
                "accepted a broken scene ({why}); status {}",
                outcome.report.status
            ),
        });
    }
    let documented = [
        QpStatus::Solved,
        QpStatus::Inaccurate,
        QpStatus::MaxIterations,
        QpStatus::TimeLimit,
        QpStatus::PrimalInfeasible,
        QpStatus::DualInfeasible,
        QpStatus::NumericalError,
    ]
    .map(QpStatus::as_str);
    let status = outcome.report.status.as_str();
    if !documented.contains(&status) {
        fail(found, "status-documented", format!("status {status:?}"));
    }
    if status == "solved" {
        match serde_json::to_value(&outcome.report) {
            Ok(v) => {
                if let Some(bad) = first_non_finite(&v, "result") {
                    fail(found, "solved-finite", bad);
                }
            }
            Err(e) => fail(
                found,
                "solved-finite",
                format!("result does not serialize: {e}"),
            ),
        }
        for (b, fld) in outcome.fields.iter().enumerate() {
            let numbers = fld
                .displacement
                .iter()
                .flatten()
                .chain(fld.stress.iter().flatten())
                .chain(&fld.von_mises)
                .chain(&fld.contact_pressure);
            if let Some(x) = numbers.into_iter().find(|x| !x.is_finite()) {
                fail(found, "solved-finite", format!("body {b}: field value {x}"));
            }
        }
        let r = &outcome.report.residuals;
        let tol = options.tol;
        let measures = [
            ("relative_penetration", r.relative_penetration),
            ("stationarity", r.stationarity),
            ("complementarity", r.complementarity),
            ("-min_multiplier", -r.min_multiplier),
        ];
        for (what, v) in measures {
            // NaN fails too.
            if v.is_nan() || v > tol {
                fail(
                    found,
                    "solved-residuals",
                    format!("{what} = {v:e} > tol {tol:e}"),
                );
            }
        }
    }
    if status == "solved" {
        if let Some(detail) = interpenetration(&scene, &outcome) {
            fail(found, "solved-no-interpenetration", detail);
        }
        if case.at_rest {
            // Exactly zero in exact arithmetic; 1e-6 of the scene size leaves room for any
            // backend's tolerance on a problem whose answer is x = 0.
            let umax = outcome
                .fields
                .iter()
                .flat_map(|f| f.displacement.iter())
                .map(|d| d[0].hypot(d[1]))
                .fold(0.0, f64::max);
            if umax > 1e-6 * scene.size() {
                fail(
                    found,
                    "unloaded-at-rest",
                    format!("max |u| = {umax:.3e} with no load, no prescribed value, no overlap"),
                );
            }
        }
    }
    match run::write_outputs(target, &scene, &outcome) {
        Ok(paths) => {
            for p in paths {
                let text = match std::fs::read_to_string(&p) {
                    Ok(t) => t,
                    Err(e) => {
                        fail(
                            found,
                            "outputs-well-formed",
                            format!("{}: {e}", p.display()),
                        );
                        continue;
                    }
                };
                let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
                let bad = match ext {
                    "json" => serde_json::from_str::<serde_json::Value>(&text)
                        .err()
                        .map(|e| e.to_string()),
                    "svg" | "vtu" => roxmltree::Document::parse(&text)
                        .err()
                        .map(|e| e.to_string()),
                    _ => None,
                };
                if let Some(e) = bad {
                    fail(
                        found,
                        "outputs-well-formed",
                        format!("{}: {e}", p.display()),
                    );
                }
            }
        }
        Err(e) => fail(found, "outputs-well-formed", format!("write_outputs: {e}")),
    }
}

/// The deformed boundary of body `b`: its boundary edges with displaced end points.
fn deformed_edges(outcome: &run::Outcome, b: usize) -> Vec<([f64; 2], [f64; 2])> {
    let mesh = &outcome.model.meshes[b];
    let u = &outcome.fields[b].displacement;
    let at = |n: usize| [mesh.nodes[n][0] + u[n][0], mesh.nodes[n][1] + u[n][1]];
    mesh.boundary.iter().map(|&[a, c]| (at(a), at(c))).collect()
}

/// Ray casting: is `p` inside the closed curve made of `edges`?
fn inside(p: [f64; 2], edges: &[([f64; 2], [f64; 2])]) -> bool {
    let mut crossings = 0;
    for (a, b) in edges {
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if x > p[0] {
                crossings += 1;
            }
        }
    }
    crossings % 2 == 1
}

/// Whether one body of the pair is at least 10²⁰ times stiffer than the other and has a
/// non-zero prescribed displacement: its Dirichlet-lifting forces then dominate ‖f‖₁ and the
/// rows' length scale (a known gap, see `KNOWN_GAPS` in fuzz.rs).
fn lifted_contrast(scene: &Scene, bodies: [usize; 2]) -> bool {
    let [p, q] = bodies.map(|b| scene.bodies[b].young);
    let stiff = if p >= 1e20 * q {
        bodies[0]
    } else if q >= 1e20 * p {
        bodies[1]
    } else {
        return false;
    };
    scene
        .dirichlet
        .iter()
        .any(|d| d.body == stiff && d.value.iter().any(|v| *v != 0.0))
}

/// Whether a body outside the pair is loaded (a traction, gravity on a third body, or a
/// non-zero prescribed displacement): its load is in ‖f‖₁, hence in the length scale Xᵢ of the
/// pair's rows, although it need not reach them (a known gap, see `KNOWN_GAPS` in fuzz.rs).
fn loaded_elsewhere(scene: &Scene, bodies: [usize; 2]) -> bool {
    let other = |b: usize| !bodies.contains(&b);
    scene.neumann.iter().any(|n| other(n.body))
        || (scene.gravity.is_some() && (0..scene.bodies.len()).any(other))
        || scene
            .dirichlet
            .iter()
            .any(|d| other(d.body) && d.value.iter().any(|v| *v != 0.0))
}

/// The largest violation max(0, Bu − g) of pair `pair`'s contact rows (the model's rows are in
/// pair order), in the scene's length unit.
fn rows_violation(outcome: &run::Outcome, pair: usize) -> f64 {
    let model = &outcome.model;
    let u = &outcome.solution.displacement;
    let mut first = 0;
    let mut count = 0;
    for r in &model.contacts {
        if r.pair == pair {
            count = r.rows.len();
            break;
        }
        first += r.rows.len();
    }
    let mut bu = vec![0.0; model.gap.len()];
    for (j, col) in model.constraints.outer_iterator().enumerate() {
        for (i, b) in col.iter() {
            bu[i] += b * u.get(j).copied().unwrap_or(0.0);
        }
    }
    (first..(first + count).min(bu.len()))
        .map(|i| bu[i] - model.gap[i])
        .fold(0.0, f64::max)
}

fn distance_to_edges(p: [f64; 2], edges: &[([f64; 2], [f64; 2])]) -> f64 {
    edges
        .iter()
        .map(|(a, b)| signorini_core::geometry::project_on_segment(p, *a, *b).1)
        .fold(f64::INFINITY, f64::min)
}

/// The deepest boundary node of one body of a contact pair inside the other (deformed), when
/// deeper than 1e-6 of the scene size plus 10 % of the pair's largest displacement (what the
/// node-to-segment discretisation may leave: a master node against a sagging slave segment
/// penetrates by about h²κ/8, a small fraction of the displacement).  Only checked where the
/// linear (small-displacement) model holds: the largest displacement at most 10 % of the smaller
/// body's size; beyond that, bodies may sweep through each other in the deformed picture
/// without any error of the solver.
fn interpenetration(scene: &Scene, outcome: &run::Outcome) -> Option<String> {
    let finite = outcome
        .fields
        .iter()
        .all(|f| f.displacement.iter().flatten().all(|v| v.is_finite()));
    if !finite {
        return None;
    }
    for (i, pair) in scene.contacts.iter().enumerate() {
        let umax = pair
            .bodies
            .iter()
            .flat_map(|&b| outcome.fields[b].displacement.iter())
            .map(|d| d[0].hypot(d[1]))
            .fold(0.0, f64::max);
        let smaller = pair
            .bodies
            .iter()
            .map(|&b| {
                let bb = signorini_core::geometry::bounding_box(scene.bodies[b].polygon.iter());
                (bb[1] - bb[0]).min(bb[3] - bb[2])
            })
            .fold(f64::INFINITY, f64::min);
        if umax > 0.1 * smaller {
            continue;
        }

        // Mortar rows enforce each slave node's gap only as a dual-basis-weighted mean over the
        // node's support (∫ψ_j g ≥ 0), so a slave node itself may end inside the master by a
        // fraction of the displacement varying across that support (a soft master sagging under
        // a coarse stiff slave: the nodes' weighted gaps are 0 while the node dips in); the rows
        // themselves (Bx ≤ g) are checked exactly by the residuals.  Half the largest
        // displacement is allowed there.
        let share = match pair.formulation {
            signorini_core::scene::Formulation::Mortar => 0.5,
            signorini_core::scene::Formulation::NodeToSegment => 0.1,
        };
        let tol = 1e-6 * scene.size() + share * umax;
        // Node-to-segment rows keep the slave's nodes out of the master; the master's nodes are
        // not constrained (a master corner may sink between slave nodes by O(slave hmax), a
        // discretisation error documented in docs/scene.md), so only slave nodes are checked.
        let Some(rows) = outcome.model.contacts.iter().find(|r| r.pair == i) else {
            continue;
        };
        // The pair's contact rows themselves (Bu ≤ g: the linearised constraints, not the
        // deformed geometry) violated by more than the allowance: not a discretisation effect.
        // A `solved` status then means relative_penetration = violation / Xᵢ ≤ tol with a row
        // length scale Xᵢ ≥ 10⁸ × the allowance, which is not this pair's length.
        let rows_violated = rows_violation(outcome, i);
        for (a, b) in [(rows.slave, rows.master)] {
            let edges = deformed_edges(outcome, b);
            let mesh = &outcome.model.meshes[a];
            let u = &outcome.fields[a].displacement;
            let mut deepest = (0.0_f64, [0.0, 0.0]);
            for &[n, _] in &mesh.boundary {
                let p = [mesh.nodes[n][0] + u[n][0], mesh.nodes[n][1] + u[n][1]];
                if inside(p, &edges) {
                    let d = distance_to_edges(p, &edges);
                    if d > deepest.0 {
                        deepest = (d, mesh.nodes[n]);
                    }
                }
            }
            if deepest.0 > tol {
                return Some(format!(
                    "contact #{}: body {:?} node at {:?} ends {:.3e} inside body {:?} \
                     (allowed {tol:.1e}){}",
                    i + 1,
                    scene.bodies[a].name,
                    deepest.1,
                    deepest.0,
                    scene.bodies[b].name,
                    if lifted_contrast(scene, pair.bodies) {
                        "; a prescribed displacement on a body 1e20× stiffer than its partner"
                            .to_string()
                    } else if rows_violated > tol {
                        format!(
                            "; its rows themselves are violated by {rows_violated:.3e} \
                             (relative_penetration {:.1e}): the row length scale counts {}",
                            outcome.report.residuals.relative_penetration,
                            if loaded_elsewhere(scene, pair.bodies) {
                                "a load on another body"
                            } else {
                                "forces that are not this pair's displacements"
                            }
                        )
                    } else {
                        String::new()
                    }
                ));
            }
        }
    }
    None
}
