//! The properties every scene must satisfy, checked through the library exactly as the CLI runs
//! a scene: parse, check, solve, write.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use signorini::backends::make_backend;
use signorini::run;
use signorini_core::mesh::MeshLimits;
use signorini_core::qp::{QpError, SolveOptions};
use signorini_core::scene::Scene;
use signorini_core::solve::SolveError;

use super::friction;
use super::gen::Case;
use super::penetration::interpenetration;
use super::refusal::{check_refusal, Stage, SCENE_FILE};

/// A property that failed, with what was seen.
#[derive(Debug, Clone)]
pub struct Finding {
    /// The property's name (see [`PROPERTIES`]).
    pub property: &'static str,
    /// What went wrong.
    pub detail: String,
}

/// Every property, by name.
pub const PROPERTIES: [&str; 15] = [
    // Nothing panics: not parsing, checking, solving nor writing.
    "no-panic",
    // Every stage ends: a case finishes within [`CASE_TIMEOUT`].
    "finishes",
    // The status is one of those docs/scene.md's "Statuses" table lists.
    "status-documented",
    // `solved` ⇒ every number in result.json and in the output fields is finite.
    "solved-finite",
    // `solved` ⇒ the residuals meet the tolerance asked for.
    "solved-residuals",
    // `solved` ⇒ no slave node of a pair ends inside its master by more than 1e-6 of the pair's
    // own motion: neither by its rows nor in the deformed geometry (fuzz/penetration.rs).
    "solved-no-interpenetration",
    // Nothing loaded, nothing prescribed, no initial overlap ⇒ a solved answer is at rest.
    "unloaded-at-rest",
    // A refusal names the key at fault: the one a mutation broke, else a key of the scene.
    "refusal-names-key",
    // The binary refuses what the library refuses (exit 1, or 3 for a resource) and writes
    // nothing: an absent output directory stays absent, an existing one unchanged.
    "refusal-writes-nothing",
    // `check` accepts exactly what `solve` accepts (a solve that runs counts, whatever its status).
    "check-equals-solve",
    // A broken scene (wrong array length, unknown or missing key, NaN, unknown body) is refused.
    "broken-refused",
    // An accepted scene's output files are written and well formed (JSON parses, SVG/VTU are XML).
    "outputs-well-formed",
    // `solved` ⇒ a body held by contact alone balances its load with the contact forces
    // (fuzz/friction.rs, which derives the slack from the tolerance).
    "solved-floating-statics",
    // `solved` ⇒ every frictional node's tangential traction is within μ·pressure (Coulomb) or s
    // (Tresca), up to the tolerance.
    "solved-friction-law",
    // A floating body loaded beyond its one frictional pair's capacity is never `solved`.
    "overdrag-not-solved",
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
    // The scene and its files as a user has them, for `Scene::from_toml_in` and the binary.
    let written = std::iter::once((SCENE_FILE, case.toml.as_str()))
        .chain(case.files.iter().map(|(n, t)| (n.as_str(), t.as_str())))
        .try_for_each(|(name, text)| std::fs::write(out.path().join(name), text));
    if let Err(e) = written {
        return vec![Finding {
            property: "outputs-well-formed",
            detail: format!("cannot write the case's files: {e}"),
        }];
    }
    let result = catch_unwind(AssertUnwindSafe(|| {
        run_stages(case, out.path(), &mut found)
    }));
    if let Err(p) = result {
        found.push(Finding {
            property: "no-panic",
            detail: panic_text(&*p),
        });
    }
    found
}

/// Whether a solve was refused by its backend (it cannot run this problem — it does not solve a
/// block of its rows, e.g. `clarabel/dual`'s box rows of friction —, or its own allocation would
/// not fit): `check`, which verifies what solve verifies before its backend
/// runs, does not judge that.
fn backend_refusal(e: &run::RunError) -> bool {
    matches!(
        e,
        run::RunError::Solve(SolveError::Qp(
            QpError::Unavailable { .. }
                | QpError::TooLarge { .. }
                | QpError::UnsupportedBlock { .. }
        ))
    )
}

fn fail(found: &mut Vec<Finding>, property: &'static str, detail: String) {
    found.push(Finding { property, detail });
}

/// Parse, check, solve and write the case whose files are in `dir`.
fn run_stages(case: &Case, dir: &Path, found: &mut Vec<Finding>) {
    let (toml, backend) = (&case.toml, case.backend);
    let scene = match Scene::from_toml_in(toml, dir) {
        Ok(s) => s,
        Err(e) => {
            friction::refused(toml, case.must_refuse.is_some());
            found.extend(check_refusal(case, dir, &e.to_string(), Stage::Scene));
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
        (Ok(_), Err(e)) if !backend_refusal(e) => fail(
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
    let outcome = match solved {
        Ok(o) => o,
        Err(e) => {
            // The binary solves: it can only be asked about a scene the library's solve refused.
            let stage = if backend_refusal(&e) {
                Stage::Backend
            } else {
                Stage::Solve
            };
            found.extend(check_refusal(case, dir, &e.to_string(), stage));
            return;
        }
    };
    if let Err(e) = &checked {
        found.extend(check_refusal(case, dir, &e.to_string(), Stage::Check));
    }
    if let Some(broken) = &case.must_refuse {
        found.push(Finding {
            property: "broken-refused",
            detail: format!(
                "accepted a broken scene ({}); status {}",
                broken.why, outcome.report.status
            ),
        });
    }
    let documented = documented_statuses();
    let status = outcome.report.status.as_str();
    if !documented.iter().any(|d| d == status) {
        fail(found, "status-documented", format!("status {status:?}"));
    }
    if status == "solved" {
        check_solved_finite(&outcome, found);
        check_solved_residuals(&outcome, options.tol, found);
        if let Some(detail) = interpenetration(&scene, &outcome) {
            fail(found, "solved-no-interpenetration", detail);
        }
        if case.at_rest {
            check_at_rest(&scene, &outcome, found);
        }
    }
    friction::check(&scene, &outcome, options.tol, found);
    check_outputs(dir, &scene, &outcome, found);
}

/// A `solved` result and its fields hold only finite numbers.
fn check_solved_finite(outcome: &run::Outcome, found: &mut Vec<Finding>) {
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
}

/// A `solved` result's residuals meet the tolerance.
fn check_solved_residuals(outcome: &run::Outcome, tol: f64, found: &mut Vec<Finding>) {
    let r = &outcome.report.residuals;
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

/// An unloaded scene with nothing prescribed and no overlap stays at rest.
fn check_at_rest(scene: &Scene, outcome: &run::Outcome, found: &mut Vec<Finding>) {
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

/// Every written file parses (JSON, SVG and VTU as XML).
fn check_outputs(dir: &Path, scene: &Scene, outcome: &run::Outcome, found: &mut Vec<Finding>) {
    match run::write_outputs(&dir.join("out"), scene, outcome) {
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

/// The statuses docs/scene.md's "Statuses" table lists (the contract, read independently of the
/// code's own list).
fn documented_statuses() -> Vec<String> {
    let doc = include_str!("../../../../docs/scene.md");
    let table = doc
        .split("## Statuses")
        .nth(1)
        .expect("docs/scene.md has a Statuses section");
    table
        .lines()
        .skip_while(|l| !l.starts_with("| `"))
        .take_while(|l| l.starts_with('|'))
        .filter_map(|l| l.strip_prefix("| `")?.split('`').next().map(str::to_string))
        .collect()
}
