//! Property/fuzz harness: generated scenes (valid, near-degenerate and broken) run through the
//! library as the CLI runs them — `Scene::from_toml`, `check::check`, `run::solve_scene` with a
//! rotating backend, `run::write_outputs` — and every property of `fuzz/props.rs` asserted:
//!
//! * no panic;
//! * the status is a documented one;
//! * `solved` ⇒ every number written is finite, the residuals meet the tolerance and no body
//!   ends inside another;
//! * a refusal names a key and writes nothing;
//! * `check` accepts exactly what `solve` accepts;
//! * a broken scene (wrong array length, unknown or missing key, `nan`, unknown body) is refused;
//! * accepted scenes write well-formed files.
//!
//! `fuzz_scenes` runs `PROPTEST_CASES` cases (default 300; proptest shrinks a failure to a
//! minimal scene).  `fuzz_cases_replay` replays every scene saved under `tests/fuzz-cases/`
//! (a scene headed `# fuzz-known-hang: WHY` is listed and skipped until its fix lands).
//! `fuzz_survey` (ignored; `scripts/fuzz.sh N`) runs N cases without stopping at a failure,
//! shrinks one example of each property that fails, and prints a summary.
//!
//! Properties the current code cannot meet yet are listed in [`KNOWN_GAPS`]: they are still
//! evaluated and reported by the survey, but do not fail `fuzz_scenes` or the replay.  Empty the
//! list as the fixes land.

mod fuzz {
    pub mod gen;
    pub mod props;
}

use std::collections::BTreeMap;
use std::path::PathBuf;

use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, TestRunner};

use fuzz::gen::{self, Case};
use fuzz::props::{self, Finding, PROPERTIES};
use signorini::backends::BackendKind;

/// Failures the current code is known to produce (found by this harness; see the issue-8
/// report), as (property, text the failure's detail contains — "" for any).  They are still
/// evaluated and counted by the survey, but do not fail `fuzz_scenes` or `fuzz_cases_replay`.
/// Remove an entry to turn it on once its fix is merged; every other failure is enforced now.
///
/// * A slave corner of a 10³⁰-stiff body with a prescribed displacement, against a soft one-cell
///   q1 body: every backend (measured: clarabel, osqp, pdas, dual-*) ends 2–5e-2 inside the
///   master and the core calls it `solved`, because the row's length scale ‖f‖₁/kᵢ counts the
///   stiff body's Dirichlet-lifting forces (~10²⁸) against a harmonic-mean stiffness of ~2: the
///   residual scale, not a backend, is loose there.  Found when pdas joined `BackendKind::ALL`
///   and this scene of the fixed seed went to dual-uzawa.  Open (issue 9's notes): a
///   compliance-weighted length scale Σⱼ|fⱼ|/Aⱼⱼ over the row's DOFs.
///
/// * The same loose scale wherever ‖f‖₁ holds forces that are not the pair's displacements: the
///   pair's own rows (Bu ≤ g, not the deformed geometry) end violated by far more than the
///   allowance and the core calls it `solved` (the finding's detail says "its rows themselves are
///   violated by …").  Found by the graded fuzz runs:
///   - a load on another body (seed 20261123; fuzz-cases/osqp-overlap-left-under-a-load-
///     elsewhere.toml): three stacked bodies, the top one pulled off by a traction of 1e100, the
///     lower pair overlapping by 3e-4; osqp leaves that pair's rows violated by 4.4e-5 (with
///     the CLI's default options, result.json's max_penetration is the whole 3.0e-4; clarabel,
///     pdas and dual-ssn leave 0, and so does osqp under a traction of 1e-3) and the core
///     reports `solved` with relative_penetration 8e-104 (Xᵢ ≈ 4e99);
///   - Dirichlet-lifting forces of a nearly incompressible body (ν = 0.499999999999, bulk
///     modulus ~10¹² E) pushed up by 3.7e-3 (fuzz-cases/dual-uzawa-rows-violated-under-
///     incompressible-lifting.toml): dual-uzawa stops after 10 iterations with the rows violated
///     by 1.0e-3 (clarabel, osqp, dual-ssn 0) at relative_penetration 3e-14 (Xᵢ ≈ 3e10).
///
///   Open (qp/residuals.rs, the lead's): Xᵢ from the load that can reach row i.  The
///   compliance-weighted Σⱼ|fⱼ|/Aⱼⱼ above answers lifting forces (|fⱼ|/Aⱼⱼ ≈ the prescribed
///   value); a load on another body cannot simply be dropped, since a stacked body's load does
///   reach the rows below it through contact.
const KNOWN_GAPS: &[(&str, &str)] = &[
    (
        "solved-no-interpenetration",
        "a prescribed displacement on a body 1e20× stiffer than its partner",
    ),
    ("solved-no-interpenetration", "the row length scale counts"),
];

/// True when a finding is one of the [`KNOWN_GAPS`].
fn known_gap(f: &Finding) -> bool {
    KNOWN_GAPS
        .iter()
        .any(|(p, text)| f.property == *p && f.detail.contains(text))
}

fn seed() -> u64 {
    std::env::var("FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20_261_123)
}

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(300)
}

fn enforced(findings: Vec<Finding>) -> Vec<Finding> {
    findings.into_iter().filter(|f| !known_gap(f)).collect()
}

fn describe(case: &Case, findings: &[Finding]) -> String {
    let mut s = String::new();
    for f in findings {
        s.push_str(&format!("[{}] {}\n", f.property, f.detail));
    }
    s.push_str(&format!(
        "backend: {}\nmust refuse: {:?}\nat rest: {}\n--- scene ---\n{}",
        case.backend, case.must_refuse, case.at_rest, case.toml
    ));
    s
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: cases(),
        // Every case is a full solve: shrinking a few hundred steps is plenty.
        max_shrink_iters: 400,
        failure_persistence: None,
        // Fixed (FUZZ_SEED overrides it): the suite must not pass or fail by the draw; surveys
        // (scripts/fuzz.sh) draw afresh.
        rng_seed: proptest::test_runner::RngSeed::Fixed(seed()),
        ..ProptestConfig::default()
    })]

    #[test]
    fn fuzz_scenes(case in gen::case()) {
        let found = enforced(props::run_case(&case));
        prop_assert!(found.is_empty(), "{}", describe(&case, &found));
    }
}

/// A saved scene: the TOML with a header of `# fuzz-backend: NAME` and, for a broken one,
/// `# fuzz-must-refuse: WHY`.
fn saved_case(text: &str) -> Case {
    let header = |key: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(key).map(|v| v.trim().to_string()))
    };
    let backend = header("# fuzz-backend:")
        .and_then(|b| b.parse::<BackendKind>().ok())
        .filter(|b| b.available())
        .unwrap_or(BackendKind::Clarabel);
    Case {
        toml: text.to_string(),
        must_refuse: header("# fuzz-must-refuse:"),
        backend,
        at_rest: header("# fuzz-at-rest:").is_some_and(|v| v == "true"),
    }
}

fn cases_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-cases")
}

#[test]
fn fuzz_cases_replay() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(cases_dir())
        .expect("tests/fuzz-cases")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no saved fuzz case");
    let mut failures = Vec::new();
    for path in &files {
        let case = saved_case(&std::fs::read_to_string(path).expect("read"));
        // A known hang would cost the whole timeout and leave a thread spinning: skipped while
        // it is a known gap.
        let hangs = case
            .toml
            .lines()
            .any(|l| l.starts_with("# fuzz-kind: finishes"));
        // A saved hang whose fix is open (`# fuzz-known-hang: WHY`): skipped, not muted for the
        // generated cases; remove the header when the fix lands.
        if let Some(why) = case
            .toml
            .lines()
            .find_map(|l| l.strip_prefix("# fuzz-known-hang:"))
        {
            println!("skipped, known hang ({}): {}", why.trim(), path.display());
            continue;
        }
        if hangs && KNOWN_GAPS.iter().any(|(p, _)| *p == "finishes") {
            println!(
                "skipped while `finishes` is a known gap: {}",
                path.display()
            );
            continue;
        }
        let found = enforced(props::run_case(&case));
        if !found.is_empty() {
            failures.push(format!("{}:\n{}", path.display(), describe(&case, &found)));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Shrinks `tree` while a failure of the same kind ([`props::signature`]) remains; returns the
/// last failing case.
fn shrink(tree: &mut impl ValueTree<Value = Case>, kind: &str) -> (Case, Vec<Finding>) {
    let fails = |c: &Case| {
        let f = props::run_case(c);
        f.iter().any(|x| props::signature(x) == kind).then_some(f)
    };
    let mut best = tree.current();
    let mut best_found = fails(&best).unwrap_or_default();
    // A hang is not shrunk: every failing step would cost the whole timeout and leave a thread
    // spinning.
    if kind.starts_with("finishes") || !tree.simplify() {
        return (best, best_found);
    }
    for _ in 0..300 {
        let c = tree.current();
        match fails(&c) {
            Some(f) => {
                best = c;
                best_found = f;
                if !tree.simplify() {
                    break;
                }
            }
            None => {
                if !tree.complicate() {
                    break;
                }
            }
        }
    }
    (best, best_found)
}

/// `scripts/fuzz.sh N`: N cases (PROPTEST_CASES), failures counted by property and by kind, one
/// shrunk example of each kind printed (and saved under `$FUZZ_DUMP` when set).
#[test]
#[ignore = "long: run through scripts/fuzz.sh"]
fn fuzz_survey() {
    let n = cases();
    std::panic::set_hook(Box::new(|_| {}));
    let mut runner = TestRunner::new(Config::default());
    let strategy = gen::case();
    let mut counts: BTreeMap<&'static str, usize> = BTreeMap::new();
    let mut kinds: BTreeMap<String, usize> = BTreeMap::new();
    let mut examples: BTreeMap<String, (Case, Vec<Finding>)> = BTreeMap::new();
    let mut open_kinds: std::collections::BTreeSet<String> = Default::default();
    let mut passed = 0;
    let start = std::time::Instant::now();
    let mut hangs = 0;
    let mut ran = 0;
    // An abandoned (hung) case keeps a core busy until the process exits: stop after
    // FUZZ_MAX_HANGS of them (default 2; scripts/fuzz.sh runs chunks in separate processes).
    let max_hangs: usize = std::env::var("FUZZ_MAX_HANGS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2);
    for _ in 0..n {
        if hangs >= max_hangs {
            println!("stopping early: {hangs} cases did not finish");
            break;
        }
        ran += 1;
        let mut tree = strategy.new_tree(&mut runner).expect("generate");
        let case = tree.current();
        let found = props::run_case(&case);
        if found.is_empty() {
            passed += 1;
        }
        hangs += found.iter().filter(|f| f.property == "finishes").count();
        let mut seen: Vec<&'static str> = found.iter().map(|f| f.property).collect();
        seen.sort_unstable();
        seen.dedup();
        for p in seen {
            *counts.entry(p).or_default() += 1;
        }
        let mut sigs: Vec<String> = found.iter().map(props::signature).collect();
        // Known or not is decided on the whole detail (a signature is cut at 90 characters): a
        // kind is enforced when any finding of it is not a known gap.
        for f in found.iter().filter(|f| !known_gap(f)) {
            open_kinds.insert(props::signature(f));
        }
        sigs.sort();
        sigs.dedup();
        for k in &sigs {
            *kinds.entry(k.clone()).or_default() += 1;
        }
        // Shrinking changes the tree, so one case is shrunk for one kind only: the first that
        // has no example yet (the others get theirs from a later case).
        if let Some(k) = sigs.into_iter().find(|k| !examples.contains_key(k)) {
            let example = shrink(&mut tree, &k);
            examples.insert(k, example);
        }
    }
    let _ = std::panic::take_hook();
    println!(
        "fuzz survey: {ran} cases in {:.1} s; {passed} passed every property",
        start.elapsed().as_secs_f64(),
    );
    for p in PROPERTIES {
        let c = counts.get(p).copied().unwrap_or(0);
        let gap = if KNOWN_GAPS.iter().any(|(g, _)| *g == p) {
            " (has known gaps)"
        } else {
            ""
        };
        println!("  {p:<24} {c:>7} failing case(s){gap}");
    }
    println!("\nkinds of failure (* = known gap):");
    for (k, c) in &kinds {
        let known = !open_kinds.contains(k);
        println!("  {c:>7} {} {k}", if known { "*" } else { " " });
    }
    let dump = std::env::var_os("FUZZ_DUMP").map(PathBuf::from);
    for (k, (case, found)) in &examples {
        println!("\n=== {k} ===\n{}", describe(case, found));
        if let Some(dir) = &dump {
            std::fs::create_dir_all(dir).expect("dump dir");
            let mut text = format!("# fuzz-kind: {k}\n# fuzz-backend: {}\n", case.backend);
            if let Some(why) = &case.must_refuse {
                text.push_str(&format!("# fuzz-must-refuse: {why}\n"));
            }
            if case.at_rest {
                text.push_str("# fuzz-at-rest: true\n");
            }
            text.push_str(&case.toml);
            // Named after the kind, so that later runs replace rather than pile up.
            let slug: String = k
                .chars()
                .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
                .collect::<String>()
                .split('-')
                .filter(|w| !w.is_empty())
                .collect::<Vec<_>>()
                .join("-");
            let slug: String = slug.chars().take(80).collect();
            std::fs::write(dir.join(format!("{slug}.toml")), text).expect("dump");
        }
    }
    let enforced: Vec<&String> = kinds.keys().filter(|k| open_kinds.contains(*k)).collect();
    assert!(
        enforced.is_empty(),
        "failures outside KNOWN_GAPS: {enforced:?}"
    );
}
