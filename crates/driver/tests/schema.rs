//! The published contract: `signorini schema scene|result` print JSON Schemas that every fixture
//! and every `result.json` satisfy, that refuse what the program refuses (a typo key, a missing
//! field), and `result.json`'s `provenance` traces the run (version, scene hash, settings,
//! cores).  Validation is by an independent validator (the `jsonschema` crate), never by the
//! types that generated the schema.

mod common;
use common::signorini;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The schema printed by `signorini schema <document>`, compiled.
fn schema(document: &str) -> jsonschema::Validator {
    let o = signorini(&["schema", document], Path::new("."));
    assert!(o.status.success(), "{}", stderr(&o));
    let value: Value = serde_json::from_slice(&o.stdout).expect("the schema is JSON");
    assert_eq!(
        value["$schema"], "https://json-schema.org/draft/2020-12/schema",
        "{document}"
    );
    jsonschema::validator_for(&value).expect("the schema compiles")
}

/// A TOML scene as the JSON value the scene schema is about (the `toml` crate's
/// deserialisation into `serde_json::Value`: tables become objects, arrays arrays).
fn scene_json(text: &str) -> Value {
    toml::from_str(text).expect("TOML")
}

fn errors(validator: &jsonschema::Validator, instance: &Value) -> Vec<String> {
    validator
        .iter_errors(instance)
        .map(|e| format!("{} at {}", e, e.instance_path()))
        .collect()
}

#[test]
fn every_fixture_satisfies_the_scene_schema() {
    let validator = schema("scene");
    let mut checked = 0;
    for sub in ["seed", "hard", "accuracy", "gmsh", "validation", "qpset"] {
        let mut here = 0;
        for entry in std::fs::read_dir(fixtures().join(sub)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                let text = std::fs::read_to_string(&path).unwrap();
                let errs = errors(&validator, &scene_json(&text));
                assert!(errs.is_empty(), "{}: {errs:?}", path.display());
                here += 1;
            }
        }
        assert!(here > 0, "no fixture in {sub}");
        checked += here;
    }
    // fixtures/README.md lists 19 seed, 25 hard, 4 accuracy, 1 gmsh, 1 validation and 3 qpset
    // scenes today; fewer would mean the loop missed some.
    assert!(checked >= 53, "{checked}");
}

/// The schema refuses what the scene parser refuses: a misspelt key (every table has
/// `additionalProperties: false`), a misspelt choice, a wrong type, a missing required key.
#[test]
fn a_scene_with_a_typo_fails_the_schema() {
    let validator = schema("scene");
    let base = std::fs::read_to_string(fixtures().join("seed/exp2b.toml")).unwrap();
    assert!(errors(&validator, &scene_json(&base)).is_empty());
    let cases = [
        (base.replace("young = 0.0012", "yuong = 0.0012"), "yuong"),
        (
            base.replace("[[contact]]", "[[contact]]\nformulation = \"mortr\""),
            "mortr",
        ),
        (base.replace("hmax = 0.2", "hmax = \"0.2\""), "0.2"),
        (format!("titel = \"x\"\n{base}"), "titel"),
        (base.replace("poisson = 0.34", ""), "poisson"),
    ];
    for (text, word) in cases {
        assert_ne!(text, base, "the replacement for {word} did not apply");
        let errs = errors(&validator, &scene_json(&text));
        assert!(!errs.is_empty(), "{word}: the schema accepted it");
        assert!(errs.iter().any(|e| e.contains(word)), "{word}: {errs:?}");
        // The program refuses it too: the schema is the parser's contract, not a looser one.
        assert!(
            signorini_core::scene::Scene::from_toml(&text).is_err(),
            "{word}: the parser accepted it"
        );
    }
}

/// Solves the default scene into `dir/res` with `args` and returns the result.json.
fn solve(dir: &Path, args: &[&str]) -> Value {
    let mut all = vec!["solve", "--out", "res"];
    all.extend(args);
    let o = signorini(&all, dir);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    let text = std::fs::read_to_string(dir.join("res/result.json")).expect("result.json");
    serde_json::from_str(&text).expect("result.json is JSON")
}

#[test]
fn results_satisfy_the_result_schema_and_record_their_provenance() {
    let validator = schema("result");
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    let text = std::fs::read_to_string(fixtures().join("seed/exp2b.toml")).unwrap();
    std::fs::write(&scene, &text).unwrap();
    let scene_arg = scene.to_str().unwrap();

    // One backend, with a time limit.
    let r = solve(
        dir.path(),
        &[
            scene_arg,
            "--backend",
            "clarabel",
            "--tol",
            "1e-8",
            "--time-limit",
            "600",
        ],
    );
    let errs = errors(&validator, &r);
    assert!(errs.is_empty(), "{errs:?}");
    assert!(r.get("attempts").is_none());
    let p = &r["provenance"];
    assert_eq!(p["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(p["scene_path"], scene_arg);
    // SHA-256 of the file's bytes, by `sha256sum` (coreutils) when present: an implementation
    // independent of the program's.
    let hash = p["scene_sha256"].as_str().unwrap();
    assert_eq!(hash.len(), 64);
    assert!(hash
        .bytes()
        .all(|b| b.is_ascii_hexdigit() && !b.is_ascii_uppercase()));
    if let Ok(o) = Command::new("sha256sum").arg(&scene).output() {
        if o.status.success() {
            let out = String::from_utf8_lossy(&o.stdout);
            assert_eq!(out.split_whitespace().next(), Some(hash));
        }
    }
    assert_eq!(p["settings"]["backend"], "clarabel");
    assert_eq!(p["settings"]["form"], "primal");
    assert_eq!(p["settings"]["tolerance"], 1e-8);
    assert_eq!(p["settings"]["time_limit_s"], 600.0);
    assert!(p["settings"].get("chain").is_none());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    assert_eq!(p["cores"], cores);

    // The file's bytes, not its meaning: a comment changes the hash.
    std::fs::write(&scene, format!("# a comment\n{text}")).unwrap();
    let r2 = solve(
        dir.path(),
        &[scene_arg, "--backend", "clarabel", "--form", "dual"],
    );
    assert!(errors(&validator, &r2).is_empty());
    assert_ne!(r2["provenance"]["scene_sha256"], hash);
    assert_eq!(r2["provenance"]["settings"]["backend"], "clarabel/dual");
    assert_eq!(r2["provenance"]["settings"]["form"], "dual");

    // The auto chain: attempts, chosen and reason are in the schema too; the built-in scene
    // has no path.
    let r3 = solve(
        dir.path(),
        &["--backend", "auto", "--chain", "dual-ssn, clarabel"],
    );
    let errs = errors(&validator, &r3);
    assert!(errs.is_empty(), "{errs:?}");
    assert!(!r3["attempts"].as_array().unwrap().is_empty());
    assert!(r3["provenance"].get("scene_path").is_none());
    assert_eq!(
        r3["provenance"]["settings"]["chain"],
        serde_json::json!(["dual-ssn", "clarabel"])
    );
    // auto picks a form per attempt (each attempt names its backend): not "primal".
    assert_eq!(r3["provenance"]["settings"]["form"], "auto");

    // Warnings of every shape the fixtures produce (a point, counts, a reason) are in it.
    for (fixture, kinds) in [
        ("initial-overlap", ["initial_overlap", "unmatched_nodes"]),
        ("inert-rows", ["inert_rows", "no_contact_row"]),
    ] {
        let path = fixtures().join(format!("hard/{fixture}.toml"));
        let r = solve(dir.path(), &[path.to_str().unwrap()]);
        let errs = errors(&validator, &r);
        assert!(errs.is_empty(), "{fixture}: {errs:?}");
        let found: Vec<&str> = r["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .map(|w| w["kind"].as_str().unwrap())
            .collect();
        for kind in kinds {
            assert!(found.contains(&kind), "{fixture}: {found:?}");
        }
    }

    // serde_json writes a non-finite number as null (unmeasurable residuals are infinite): the
    // schema allows null where a number goes, and nothing else.
    let mut odd = r.clone();
    odd["residuals"]["stationarity"] = Value::Null;
    assert!(errors(&validator, &odd).is_empty());
    odd["residuals"]["stationarity"] = serde_json::json!("inf");
    assert!(!errors(&validator, &odd).is_empty());

    // The schema is not vacuous: a missing field, a wrong type, an unknown warning kind fail.
    let mut bad = r.clone();
    bad.as_object_mut().unwrap().remove("status");
    assert!(!errors(&validator, &bad).is_empty());
    let mut bad = r.clone();
    bad["status"] = serde_json::json!("sloved");
    assert!(!errors(&validator, &bad).is_empty());
    let mut bad = r.clone();
    bad["dofs"] = serde_json::json!("many");
    assert!(!errors(&validator, &bad).is_empty());
    let mut bad = r.clone();
    bad["warnings"] = serde_json::json!([{"message": "m", "kind": "no_such_kind"}]);
    assert!(!errors(&validator, &bad).is_empty());
}

/// Backend names are clap choices: help lists them, a typo gets clap's suggestion and the
/// message names every valid backend; longer spellings of before still work.
#[test]
fn backend_names_are_listed_and_typos_get_suggestions() {
    let dir = tempfile::tempdir().unwrap();
    let names = [
        "auto",
        "clarabel",
        "osqp",
        "dual-pgs",
        "dual-uzawa",
        "dual-ssn",
        "pdas",
        "clarabel/dual",
        "osqp/dual",
    ];
    let o = signorini(&["solve", "--help"], dir.path());
    let help = String::from_utf8_lossy(&o.stdout);
    for name in names {
        assert!(
            help.contains(&format!("- {name}:")),
            "{name} not in help: {help}"
        );
    }
    let o = signorini(
        &["solve", "--backend", "clarabl", "--out", "res"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(err.contains("unknown backend \"clarabl\""), "{err}");
    assert!(err.contains("a similar value exists: 'clarabel'"), "{err}");
    for name in names {
        assert!(err.contains(name), "{name} not named: {err}");
    }
    let o = signorini(
        &["compare", "--forms", "primal,duel", "--out", "res"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("'dual'"), "{}", stderr(&o));
    assert!(!dir.path().join("res").exists());
    // The study's choices too (their own messages kept, clap's suggestion added).
    let o = signorini(
        &[
            "study",
            "--hmax",
            "0.2",
            "--formulations",
            "mortr",
            "--out",
            "res",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(err.contains("node-to-segment or mortar"), "{err}");
    assert!(err.contains("a similar value exists: 'mortar'"), "{err}");
    let o = signorini(&["study", "--help"], dir.path());
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(
        help.contains("[possible values: uniform, graded]"),
        "{help}"
    );
    assert!(!dir.path().join("res").exists());
    // `name/form` spellings and spaces around list items keep working.
    let r = solve(dir.path(), &["--backend", " dual-ssn/dual "]);
    assert_eq!(r["backend"], "dual-ssn");
}

/// Every committed expectation satisfies `signorini schema expectation`, which refuses a
/// misspelt key and a status that does not exist.
#[test]
fn every_expectation_satisfies_its_schema() {
    let validator = schema("expectation");
    let mut checked = 0;
    for sub in ["seed", "hard", "gmsh"] {
        for entry in std::fs::read_dir(fixtures().join(sub)).unwrap() {
            let path = entry.unwrap().path();
            if path.to_string_lossy().ends_with(".expected.json") {
                let value: Value =
                    serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
                let errs = errors(&validator, &value);
                assert!(errs.is_empty(), "{}: {errs:?}", path.display());
                checked += 1;
            }
        }
    }
    // One per seed (19), hard (29) and gmsh (1) scene.
    assert_eq!(checked, 49);
    let bad = serde_json::json!({"status": "solved", "rtol": {"objetive": 1e-3}});
    assert!(!errors(&validator, &bad).is_empty());
    let bad = serde_json::json!({"status": "perhaps"});
    assert!(!errors(&validator, &bad).is_empty());
    assert!(errors(&validator, &serde_json::json!({"status": "not-solved"})).is_empty());
}

/// A suite.json with every part present — a regression, an expected failure, a scene without
/// solution, a case error, a linear-solve case, a baseline — satisfies `signorini schema suite`.
#[test]
fn suite_json_satisfies_its_schema() {
    let dir = tempfile::tempdir().unwrap();
    for f in [
        "hard/floating-free",
        "hard/inert-rows",
        "hard/stiffness-contrast",
        "seed/exp2b",
    ] {
        let scene = fixtures().join(format!("{f}.toml"));
        let name = scene.file_name().unwrap().to_owned();
        std::fs::copy(&scene, dir.path().join(&name)).unwrap();
        let expected = fixtures().join(format!("{f}.expected.json"));
        let target = dir.path().join(expected.file_name().unwrap());
        std::fs::copy(&expected, target).unwrap();
    }
    // exp2b's expectation broken (a regression), a scene that does not parse (a case error).
    let path = dir.path().join("exp2b.expected.json");
    let mut e: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    e["figures"]["max_displacement"] = serde_json::json!(1.0);
    std::fs::write(&path, e.to_string()).unwrap();
    std::fs::write(dir.path().join("broken.toml"), "[[body]]").unwrap();
    let backends = if cfg!(feature = "osqp") {
        "clarabel,osqp,pdas"
    } else {
        "clarabel,pdas"
    };
    let o = signorini(
        &["suite", ".", "--backends", backends, "--out", "a"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = signorini(
        &[
            "suite",
            ".",
            "--backends",
            backends,
            "--out",
            "b",
            "--baseline",
            "a/suite.json",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("b/suite.json")).unwrap())
            .unwrap();
    assert!(report["baseline"].is_object());
    let errs = errors(&schema("suite"), &report);
    assert!(errs.is_empty(), "{errs:?}");
    // The schema is not vacuous: a verdict that does not exist is refused.
    let mut bad = report.clone();
    let case = bad["cases"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|c| c["name"] == "exp2b")
        .unwrap();
    case["runs"][0]["verdict"] = serde_json::json!("maybe");
    assert!(!errors(&schema("suite"), &bad).is_empty());
}

/// A frictional result (Coulomb, a load path) satisfies the result schema with its new fields
/// (tangential figures, states, `coulomb`, `steps`), and the schema refuses a state that does
/// not exist.
#[test]
fn frictional_results_satisfy_the_result_schema() {
    let validator = schema("result");
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(fixtures().join("hard/friction-slide.toml"))
        .unwrap()
        .replace(
            "[[neumann]]\nbody = \"block\"",
            "[[neumann]]\nname = \"press\"\nbody = \"block\"",
        );
    let text = format!("{text}\n[[step]]\nloads = {{ press = 1.0 }}\nincrements = 2\n");
    std::fs::write(dir.path().join("scene.toml"), &text).unwrap();
    let r = solve(dir.path(), &["scene.toml"]);
    let errs = errors(&validator, &r);
    assert!(errs.is_empty(), "{errs:?}");
    assert_eq!(r["steps"].as_array().unwrap().len(), 2);
    assert!(r["coulomb"]["outer_iterations"].as_u64().unwrap() >= 1);
    let node = &r["contacts"][0]["nodes"][0];
    assert!(node["state"].is_string() && node["tangential_traction"].is_number());
    let mut bad = r.clone();
    bad["contacts"][0]["nodes"][0]["state"] = "sliding".into();
    assert!(!errors(&validator, &bad).is_empty());
}
