//! Property/fuzz harness: generated scenes (valid, near-degenerate and broken) run through the
//! library as the CLI runs them — `Scene::from_toml`, `check::check`, `run::solve_scene` with a
//! rotating backend, `run::write_outputs` — and every property of `fuzz/props.rs` asserted:
//!
//! * no panic;
//! * the status is a documented one;
//! * `solved` ⇒ every number written is finite, the residuals meet the tolerance and no slave
//!   node ends inside its master by more than 1e-6 of the pair's own motion (its rows and the
//!   deformed geometry, fuzz/penetration.rs);
//! * a refusal names the key at fault (the very key a mutation broke), and the binary refuses
//!   the same scene file (exit 1, or 3 for a resource limit) and writes nothing;
//! * `check` accepts exactly what `solve` accepts;
//! * a broken scene (wrong array length, unknown or missing key, `nan`, unknown body) is refused;
//! * accepted scenes write well-formed files.
//!
//! `fuzz_scenes` runs `PROPTEST_CASES` cases (default 300; proptest shrinks a failure to a
//! minimal scene).  `fuzz_cases_replay` replays every scene saved under `tests/fuzz-cases/`
//! (a scene headed `# fuzz-known-hang: WHY` is listed and skipped until its fix lands; one
//! headed `# fuzz-open: WHY` is a failure whose fix is open, run strictly by the ignored
//! `fuzz_open_cases`).
//! `fuzz_survey` (ignored; `scripts/fuzz.sh N`) runs N cases without stopping at a failure,
//! shrinks one example of each property that fails, and prints a summary.
//!
//! Every property is enforced: nothing is muted by the text of its finding.  A finding whose
//! fix is open stays failing (its replay in `tests/fuzz-cases/` fails `fuzz_cases_replay`) until
//! the fix lands.
//!
//! The generator draws what users run: the default backend `auto` most often, every other name
//! (`clarabel/dual` and `osqp/dual` included), node-to-segment and mortar pairs, graded meshes
//! (`[[body.refine]]`) and Gmsh meshes (MSH 4.1 files it writes beside the scene).

mod fuzz {
    pub mod friction;
    pub mod gen;
    pub mod msh;
    pub mod penetration;
    pub mod props;
    pub mod refusal;
}

use std::collections::BTreeMap;
use std::path::PathBuf;

use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, TestRunner};

use fuzz::gen::{self, Broken, Case};
use fuzz::props::{self, Finding, PROPERTIES};
use signorini::backends::BackendKind;

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

fn describe(case: &Case, findings: &[Finding]) -> String {
    let mut s = String::new();
    for f in findings {
        s.push_str(&format!("[{}] {}\n", f.property, f.detail));
    }
    s.push_str(&format!(
        "backend: {}\nmust refuse: {:?}\nat rest: {}\n--- scene ---\n{}",
        case.backend,
        case.must_refuse.as_ref().map(|b| &b.why),
        case.at_rest,
        case.toml
    ));
    for (name, _) in &case.files {
        s.push_str(&format!("--- with {name} (see the saved replay) ---\n"));
    }
    s
}

/// Marks the lines of a file embedded in a saved case.
const FILE_LINE: &str = "#| ";

/// A saved case's text: the header (`# fuzz-kind`, `# fuzz-backend`, `# fuzz-must-refuse`,
/// `# fuzz-at-rest`), every file the scene refers to as `# fuzz-file: NAME` followed by its lines
/// prefixed with `#| ` (TOML comments, so the scene stays one self-contained file), then the scene.
fn saved_text(kind: &str, case: &Case) -> String {
    let mut text = format!("# fuzz-kind: {kind}\n# fuzz-backend: {}\n", case.backend);
    if let Some(broken) = &case.must_refuse {
        text.push_str(&format!("# fuzz-must-refuse: {}\n", broken.why));
    }
    if case.at_rest {
        text.push_str("# fuzz-at-rest: true\n");
    }
    for (name, body) in &case.files {
        text.push_str(&format!("# fuzz-file: {name}\n"));
        for line in body.lines() {
            text.push_str(FILE_LINE);
            text.push_str(line);
            text.push('\n');
        }
    }
    text.push_str(&case.toml);
    text
}

/// The files embedded in a saved case (see [`saved_text`]).
fn saved_files(text: &str) -> Vec<(String, String)> {
    let mut files: Vec<(String, String)> = Vec::new();
    for line in text.lines() {
        if let Some(name) = line.strip_prefix("# fuzz-file:") {
            files.push((name.trim().to_string(), String::new()));
        } else if let (Some(body), Some((_, file))) =
            (line.strip_prefix(FILE_LINE), files.last_mut())
        {
            file.push_str(body);
            file.push('\n');
        }
    }
    files
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
        let found = props::run_case(&case);
        prop_assert!(found.is_empty(), "{}", describe(&case, &found));
    }
}

/// A saved scene ([`saved_text`]): the TOML with a header of `# fuzz-backend: NAME`, for a
/// broken one `# fuzz-must-refuse: WHY` (the key it broke backticked first), and its files.
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
        files: saved_files(text),
        must_refuse: header("# fuzz-must-refuse:").map(|why| Broken::from_why(&why)),
        backend,
        at_rest: header("# fuzz-at-rest:").is_some_and(|v| v == "true"),
    }
}

fn cases_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-cases")
}

/// The saved case files, sorted.
fn case_paths() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(cases_dir())
        .expect("tests/fuzz-cases")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no saved fuzz case");
    files
}

/// The text after `header` on a line of the case, when it has one.
fn header<'a>(case: &'a Case, header: &str) -> Option<&'a str> {
    case.toml.lines().find_map(|l| l.strip_prefix(header))
}

/// Runs every saved case that `select` keeps and fails listing each one that breaks a property.
fn replay(select: impl Fn(&Case, &PathBuf) -> bool) {
    let mut failures = Vec::new();
    for path in &case_paths() {
        let case = saved_case(&std::fs::read_to_string(path).expect("read"));
        if !select(&case, path) {
            continue;
        }
        let found = props::run_case(&case);
        if !found.is_empty() {
            failures.push(format!("{}:\n{}", path.display(), describe(&case, &found)));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn fuzz_cases_replay() {
    replay(|case, path| {
        // A saved hang whose fix is open (`# fuzz-known-hang: WHY`), or a saved failure whose
        // fix is open (`# fuzz-open: WHY`, run strictly by `fuzz_open_cases`): skipped here,
        // never muted for the generated cases; remove the header when the fix lands.
        for (tag, what) in [
            ("# fuzz-known-hang:", "known hang"),
            ("# fuzz-open:", "open gap"),
        ] {
            if let Some(why) = header(case, tag) {
                println!("skipped, {what} ({}): {}", why.trim(), path.display());
                return false;
            }
        }
        true
    });
}

/// The saved failures whose fix is open, each with every property enforced: this test fails
/// until they are fixed (run it with `--ignored`; the cases and why are listed in README's
/// Fuzzing section).
#[ignore = "the saved failures headed # fuzz-open, whose fix is open (README, Fuzzing): fails until each is fixed"]
#[test]
fn fuzz_open_cases() {
    replay(|case, _| header(case, "# fuzz-open:").is_some());
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
        println!("  {p:<24} {c:>7} failing case(s)");
    }
    println!("\nfrictional cases (fuzz/friction.rs):");
    for (label, c) in fuzz::friction::tally() {
        println!("  {c:>7} {label}");
    }
    println!("\nkinds of failure:");
    for (k, c) in &kinds {
        println!("  {c:>7} {k}");
    }
    let dump = std::env::var_os("FUZZ_DUMP").map(PathBuf::from);
    for (k, (case, found)) in &examples {
        println!("\n=== {k} ===\n{}", describe(case, found));
        if let Some(dir) = &dump {
            std::fs::create_dir_all(dir).expect("dump dir");
            let text = saved_text(k, case);
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
    assert!(kinds.is_empty(), "failures: {:?}", kinds.keys());
}

/// The generator's Gmsh files are read as the grids they describe, triangles and quadrilaterals
/// listed either way round (else every Gmsh case would only exercise a refusal): a 3 × 2 grid
/// on [0, 3] × [0, 2] has 6 quadrilaterals or 12 triangles and 12 nodes, 4 of them on the
/// clamped bottom edge, hence 2 · (12 − 4) = 16 free DOFs.
#[test]
fn generated_gmsh_files_are_read_as_written() {
    let scene = "[[body]]\nname = \"b\"\nmesh = \"b.msh\"\nyoung = 1.0\npoisson = 0.3\n\n\
                 [[dirichlet]]\nbody = \"b\"\nregion = [0.0, 3.0, 0.0, 0.0]\n";
    for (quads, clockwise) in [(false, false), (false, true), (true, false), (true, true)] {
        let dir = tempfile::tempdir().expect("temporary directory");
        let grid = fuzz::msh::grid([0.0, 3.0, 0.0, 2.0], [3, 2], quads, clockwise);
        std::fs::write(dir.path().join("b.msh"), grid).expect("write b.msh");
        let scene = signorini_core::scene::Scene::from_toml_in(scene, dir.path())
            .unwrap_or_else(|e| panic!("quads {quads}, clockwise {clockwise}: {e}"));
        let report = signorini::check::check(&scene, &props::limits())
            .unwrap_or_else(|e| panic!("quads {quads}, clockwise {clockwise}: {e}"));
        assert_eq!(report.elements, if quads { 6 } else { 12 });
        assert_eq!(report.dofs, 16);
    }
}
