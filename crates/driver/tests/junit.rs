//! `suite.xml` is valid JUnit: an independent validator, `xmllint --schema` (libxml2), checks
//! the file the binary writes against the Jenkins xunit plugin's `junit-10.xsd`
//! (tests/data/junit-10.xsd, its source and licence in its header), on a suite holding every
//! kind of outcome: a pass, a regression, a case without expectation, a case that could not
//! run, a case without contact rows.
#![allow(clippy::unwrap_used)]

mod common;
use common::{repo, signorini};

use std::path::{Path, PathBuf};
use std::process::Command;

/// `xmllint --noout --schema junit-10.xsd FILE`: Ok, or the validator's complaint.  Panics —
/// the test fails, it is not skipped — when xmllint is not installed.
fn validate(file: &Path) -> Result<(), String> {
    let xsd = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/junit-10.xsd");
    let o = Command::new("xmllint")
        .arg("--noout")
        .arg("--schema")
        .arg(&xsd)
        .arg(file)
        .output()
        .unwrap_or_else(|e| {
            panic!(
                "xmllint could not be run ({e}): install it with `apt-get install -y libxml2-utils` (Debian; .ci/run does)"
            )
        });
    if o.status.success() {
        Ok(())
    } else {
        Err(String::from_utf8_lossy(&o.stderr).into_owned())
    }
}

/// One block on the ground, loaded: no contact pair, so one linear solve (`cholesky`).
const NO_CONTACT: &str = r#"title = "one block"
[[body]]
name = "b"
polygon = [[0, 0], [1, 0], [1, 1], [0, 1]]
hmax = 0.5
young = 1
poisson = 0.3
[[dirichlet]]
body = "b"
region = [0, 1, 0, 0]
[[neumann]]
body = "b"
region = [0, 1, 1, 1]
traction = [0, -0.01]
"#;

#[test]
fn the_suite_xml_the_binary_writes_is_valid_junit() {
    let dir = tempfile::tempdir().unwrap();
    let suite = dir.path().join("s");
    std::fs::create_dir(&suite).unwrap();
    let exp1 = repo("fixtures/seed/exp1.toml");
    let expected = std::fs::read_to_string(repo("fixtures/seed/exp1.expected.json")).unwrap();
    // A pass, and the same scene with a wrong objective: a regression.
    std::fs::copy(&exp1, suite.join("pass.toml")).unwrap();
    std::fs::write(suite.join("pass.expected.json"), &expected).unwrap();
    std::fs::copy(&exp1, suite.join("wrong.toml")).unwrap();
    let mut wrong: serde_json::Value = serde_json::from_str(&expected).unwrap();
    let objective = wrong["figures"]["objective"].as_f64().unwrap();
    wrong["figures"]["objective"] = (2.0 * objective).into();
    std::fs::write(suite.join("wrong.expected.json"), wrong.to_string()).unwrap();
    // No expectation; cannot be read; no contact row.
    std::fs::copy(&exp1, suite.join("unchecked.toml")).unwrap();
    std::fs::write(suite.join("broken.toml"), "title = \"broken\"\n[[body]\n").unwrap();
    std::fs::write(suite.join("free.toml"), NO_CONTACT).unwrap();
    let o = signorini(
        &["suite", "s", "--backends", "clarabel,pdas", "--out", "out"],
        dir.path(),
    );
    // Regressions and a case without expectation: exit 2, the files written.
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let xml_path = dir.path().join("out/suite.xml");
    let xml = std::fs::read_to_string(&xml_path).unwrap();
    for element in ["<failure", "<error", "<skipped", "<properties>"] {
        assert!(xml.contains(element), "{element} missing from\n{xml}");
    }
    if let Err(why) = validate(&xml_path) {
        panic!("suite.xml is not valid junit-10.xsd:\n{why}\n{xml}");
    }
    // The validator can fail: the same document with a test case that has no name is refused.
    let bad = dir.path().join("bad.xml");
    std::fs::write(&bad, xml.replacen("<testcase name=", "<testcase nom=", 1)).unwrap();
    let why = validate(&bad).expect_err("xmllint accepted a nameless testcase");
    assert!(why.contains("nom"), "{why}");
}
