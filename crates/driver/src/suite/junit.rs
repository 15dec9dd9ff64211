//! `suite.xml`: the suite in JUnit's XML format, one test case per (scene, backend), so that CI
//! systems (GitHub Actions reporters such as dorny/test-reporter or mikepenz/action-junit-report,
//! GitLab's `artifacts:reports:junit`, Jenkins) list each case.
//!
//! The document:
//!
//! ```text
//! <?xml version="1.0" encoding="UTF-8"?>
//! <testsuites name="signorini suite" tests="…" failures="…" errors="…" time="…">
//!   <testsuite name="BACKEND" tests="…" failures="…" errors="…" skipped="…" time="…">
//!     <properties><property name="dir" value="…"/><property name="tolerance" value="…"/>…</properties>
//!     <testcase name="CASE" classname="signorini.suite.BACKEND" time="…">…</testcase>
//!   </testsuite>
//! </testsuites>
//! ```
//!
//! * One `<testsuite>` per backend of [`SuiteReport::backends`], in that order, holding one
//!   `<testcase>` per case the backend ran (`time` = its solve time).
//! * A case without contact rows has a single `cholesky` run (one linear solve, no backend runs):
//!   those runs form one more `<testsuite name="cholesky">` after the backends' (any run of a
//!   backend not listed in `backends` gets a suite of its own the same way).  Putting them in
//!   every backend's suite would count one linear solve once per backend; a suite of their own
//!   keeps each backend's `tests` equal to the cases it ran.
//! * Verdicts ([`Verdict`]): `pass` → an empty `<testcase/>`; `fail` →
//!   `<failure message="first note" type="regression">` whose text lists every note, the status
//!   and the backend's message; `expected-failure` → `<skipped message="expected failure: status
//!   …"/>`; `unexpected-pass` → a pass with a `<system-out>` saying so (refresh the expectation
//!   with `--bless`); `unchecked` (no expectation) → `<skipped message="no expectation: run with
//!   --bless"/>`.
//! * A case that could not run at all ([`CaseReport::error`]) is an `<error
//!   message="…" type="case-error">` in every backend's suite: each backend shows the regression.
//! * `failures` counts `fail`, `errors` case errors, `skipped` expected failures and unchecked
//!   runs; the root's counts and times are the sums over its suites.  The root has no `skipped`
//!   attribute: the Jenkins xunit plugin's `junit-10.xsd` does not allow one there (each
//!   `<testsuite>` carries its own).
//! * A test case's time is seconds with a dot and six decimals; a `<testsuite>`'s and the
//!   root's have three, as `junit-10.xsd`'s `SUREFIRE_TIME` pattern requires there (at most
//!   three decimals: `0.029276` is refused by the schema).  A time that is NaN (a backend that
//!   could not run), infinite or negative is written as zero.
//! * Every text is escaped ([`xml_escape`]; characters XML 1.0 forbids become U+FFFD); tab,
//!   newline and carriage return inside attribute values are written as character references so
//!   that a parser gives them back unchanged.
//!
//! The document is valid against the Jenkins xunit plugin's JUnit schema (`junit-10.xsd`, which
//! requires `name`, `tests`, `failures` and `errors` on `<testsuite>` and `name` on `<testcase>`);
//! every `<testsuite>` also carries `time` and every `<testcase>` `classname` and `time`.

use super::report::{CaseReport, CaseRun, SuiteReport, Verdict};
use crate::output::xml_escape;

/// The root element's `name`.
const ROOT_NAME: &str = "signorini suite";
/// Prefix of every test case's `classname` (the backend follows).
const CLASSNAME_PREFIX: &str = "signorini.suite.";
/// `type` of a `<failure>`.
const FAILURE_TYPE: &str = "regression";
/// `type` of an `<error>`.
const ERROR_TYPE: &str = "case-error";
/// `message` of the `<skipped>` of a case without expectation.
const UNCHECKED_MESSAGE: &str = "no expectation: run with --bless";
/// The suite holding case errors when the report names no backend (so that no error is lost).
const NO_BACKEND_SUITE: &str = "signorini";

/// What a test case concluded.
enum Outcome {
    /// Passed (no child element).
    Pass,
    /// `<failure>`.
    Failure { message: String, text: String },
    /// `<error>`.
    Error { message: String, text: String },
    /// `<skipped>`, with a text when there is something to add.
    Skipped { message: String, text: String },
}

/// One `<testcase>`.
struct TestCase {
    /// The case's name.
    name: String,
    /// The backend (the classname is derived from it).
    backend: String,
    /// Seconds (any value: [`seconds`] cleans it).
    time: f64,
    /// The verdict's element.
    outcome: Outcome,
    /// The `<system-out>` text, if any.
    system_out: Option<String>,
}

/// One `<testsuite>`.
struct Suite {
    /// The backend.
    name: String,
    /// Its test cases, in the order of the report's cases.
    cases: Vec<TestCase>,
}

impl Suite {
    /// `(tests, failures, errors, skipped)`.
    fn counts(&self) -> (usize, usize, usize, usize) {
        let mut c = (self.cases.len(), 0, 0, 0);
        for t in &self.cases {
            match t.outcome {
                Outcome::Pass => {}
                Outcome::Failure { .. } => c.1 += 1,
                Outcome::Error { .. } => c.2 += 1,
                Outcome::Skipped { .. } => c.3 += 1,
            }
        }
        c
    }

    /// Sum of the test cases' times, seconds (cleaned as written).
    fn time(&self) -> f64 {
        self.cases.iter().map(|t| clean_time(t.time)).sum()
    }
}

/// A time as written: NaN, infinite and negative values become 0.
fn clean_time(t: f64) -> f64 {
    if t.is_finite() && t > 0.0 {
        t
    } else {
        0.0
    }
}

/// A test case's time: seconds with a dot and six decimals (never an exponent).
fn seconds(t: f64) -> String {
    format!("{:.6}", clean_time(t))
}

/// A `<testsuite>`'s or the root's time: seconds with a dot and three decimals, as
/// `junit-10.xsd`'s `SUREFIRE_TIME` allows (never an exponent).
fn suite_seconds(t: f64) -> String {
    format!("{:.3}", clean_time(t))
}

/// `text` for a quoted attribute value: [`xml_escape`]d, and tab, newline and carriage return
/// written as character references (a parser would turn them into spaces otherwise).
fn attr(text: &str) -> String {
    xml_escape(text)
        .replace('\t', "&#9;")
        .replace('\n', "&#10;")
        .replace('\r', "&#13;")
}

/// `text` as character data: [`xml_escape`]d, and carriage return written as a reference (a
/// parser would turn it into a newline otherwise).
fn chars(text: &str) -> String {
    xml_escape(text).replace('\r', "&#13;")
}

/// The lines explaining a run: its notes, status, backend's message and time.
fn details(run: &CaseRun) -> String {
    let mut lines: Vec<String> = run.notes.clone();
    lines.push(format!(
        "status: {} (backend status: {}, {} iterations)",
        run.status, run.backend_status, run.iterations
    ));
    if let Some(m) = &run.message {
        lines.push(format!("message: {m}"));
    }
    if run.solve_s.is_finite() {
        let mut line = format!("solve time: {} s", seconds(run.solve_s));
        if run.ratio_to_floor.is_finite() {
            line.push_str(&format!(" ({:.3} × floor)", run.ratio_to_floor));
        }
        lines.push(line);
    }
    lines.join("\n")
}

/// The test case of one run.
fn run_case(case: &CaseReport, run: &CaseRun) -> TestCase {
    let mut system_out = None;
    let outcome = match run.verdict {
        Verdict::Pass => {
            if !run.notes.is_empty() {
                system_out = Some(run.notes.join("\n"));
            }
            Outcome::Pass
        }
        Verdict::Fail => Outcome::Failure {
            message: run
                .notes
                .first()
                .cloned()
                .unwrap_or_else(|| format!("status {}", run.status)),
            text: details(run),
        },
        Verdict::ExpectedFailure => Outcome::Skipped {
            message: format!("expected failure: status {}", run.status),
            text: details(run),
        },
        Verdict::UnexpectedPass => {
            let mut out = format!(
                "unexpected pass: {} solved this case within every tolerance although the \
                 expectation says it fails; refresh the expectation with --bless",
                run.backend
            );
            for n in &run.notes {
                out.push('\n');
                out.push_str(n);
            }
            system_out = Some(out);
            Outcome::Pass
        }
        Verdict::Unchecked => Outcome::Skipped {
            message: UNCHECKED_MESSAGE.to_string(),
            text: details(run),
        },
    };
    TestCase {
        name: case.name.clone(),
        backend: run.backend.clone(),
        time: run.solve_s,
        outcome,
        system_out,
    }
}

/// The test case of a case that could not run, in `backend`'s suite.
fn error_case(case: &CaseReport, error: &str, backend: &str) -> TestCase {
    let mut text = format!("the case could not run: {error}");
    if !case.scene.is_empty() {
        text.push_str(&format!("\nscene: {}", case.scene));
    }
    // A run of this backend, should the case have one, is told too.
    for run in case.runs.iter().filter(|r| r.backend == backend) {
        text.push('\n');
        text.push_str(&details(run));
    }
    TestCase {
        name: case.name.clone(),
        backend: backend.to_string(),
        time: 0.0,
        outcome: Outcome::Error {
            message: error.to_string(),
            text,
        },
        system_out: None,
    }
}

/// The suites: the report's backends in order, then any other backend a run names (`cholesky`),
/// in order of first appearance.
fn suites(report: &SuiteReport) -> Vec<Suite> {
    let mut names: Vec<String> = Vec::new();
    let mut add = |n: &str| {
        if !names.iter().any(|m| m == n) {
            names.push(n.to_string());
        }
    };
    report.backends.iter().for_each(|b| add(b));
    report
        .cases
        .iter()
        .flat_map(|c| &c.runs)
        .for_each(|r| add(&r.backend));
    // Where a case error goes: every backend's suite (every suite, or one of its own, when the
    // report names no backend).
    let mut error_suites: Vec<String> = report.backends.clone();
    if error_suites.is_empty() {
        error_suites = names.clone();
    }
    if error_suites.is_empty() && report.cases.iter().any(|c| c.error.is_some()) {
        error_suites.push(NO_BACKEND_SUITE.to_string());
        names.push(NO_BACKEND_SUITE.to_string());
    }
    names
        .into_iter()
        .map(|name| {
            let mut cases = Vec::new();
            for case in &report.cases {
                match &case.error {
                    Some(error) if error_suites.contains(&name) => {
                        cases.push(error_case(case, error, &name));
                    }
                    _ => cases.extend(
                        case.runs
                            .iter()
                            .filter(|r| r.backend == name)
                            .map(|r| run_case(case, r)),
                    ),
                }
            }
            Suite { name, cases }
        })
        .collect()
}

/// The `<property>` elements: where the run comes from and what it asked for.
fn properties(report: &SuiteReport) -> Vec<(&'static str, String)> {
    let mut p = vec![
        ("dir", report.dir.clone()),
        ("tolerance", format!("{:e}", report.tolerance)),
    ];
    if let Some(t) = report.time_limit_s {
        p.push(("time_limit_s", format!("{t}")));
    }
    if let Some(prov) = &report.provenance {
        p.push(("version", prov.version.clone()));
        if let Some(c) = &prov.commit {
            p.push(("commit", c.clone()));
        }
        p.push(("cores", prov.cores.to_string()));
    }
    p
}

/// Writes one `<testcase>`.
fn write_case(out: &mut String, t: &TestCase) {
    let open = format!(
        "    <testcase name=\"{}\" classname=\"{}\" time=\"{}\"",
        attr(&t.name),
        attr(&format!("{CLASSNAME_PREFIX}{}", t.backend)),
        seconds(t.time)
    );
    out.push_str(&open);
    let child = match &t.outcome {
        Outcome::Pass => None,
        Outcome::Failure { message, text } => Some(("failure", message, Some(FAILURE_TYPE), text)),
        Outcome::Error { message, text } => Some(("error", message, Some(ERROR_TYPE), text)),
        Outcome::Skipped { message, text } => Some(("skipped", message, None, text)),
    };
    if child.is_none() && t.system_out.is_none() {
        out.push_str("/>\n");
        return;
    }
    out.push_str(">\n");
    if let Some((tag, message, kind, text)) = child {
        out.push_str(&format!("      <{tag} message=\"{}\"", attr(message)));
        if let Some(kind) = kind {
            out.push_str(&format!(" type=\"{kind}\""));
        }
        if text.is_empty() {
            out.push_str("/>\n");
        } else {
            out.push_str(&format!(">{}</{tag}>\n", chars(text)));
        }
    }
    if let Some(s) = &t.system_out {
        out.push_str(&format!("      <system-out>{}</system-out>\n", chars(s)));
    }
    out.push_str("    </testcase>\n");
}

/// The suite as JUnit XML (see the module's docs for the layout): a complete, well-formed
/// UTF-8 document whatever the report's names and messages hold.
pub fn junit_xml(report: &SuiteReport) -> String {
    let suites = suites(report);
    let props = properties(report);
    let mut body = String::new();
    let (mut tests, mut failures, mut errors, mut time) = (0, 0, 0, 0.0);
    for s in &suites {
        let (n, f, e, k) = s.counts();
        let t = s.time();
        tests += n;
        failures += f;
        errors += e;
        time += t;
        body.push_str(&format!(
            "  <testsuite name=\"{}\" tests=\"{n}\" failures=\"{f}\" errors=\"{e}\" \
             skipped=\"{k}\" time=\"{}\">\n",
            attr(&s.name),
            suite_seconds(t)
        ));
        body.push_str("    <properties>\n");
        for (name, value) in &props {
            body.push_str(&format!(
                "      <property name=\"{name}\" value=\"{}\"/>\n",
                attr(value)
            ));
        }
        body.push_str("    </properties>\n");
        for t in &s.cases {
            write_case(&mut body, t);
        }
        body.push_str("  </testsuite>\n");
    }
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <testsuites name=\"{ROOT_NAME}\" tests=\"{tests}\" failures=\"{failures}\" \
         errors=\"{errors}\" time=\"{}\">\n{body}</testsuites>\n",
        suite_seconds(time)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::xml_sanitize;
    use crate::suite::sample::{self, case, run};

    /// A backend name that needs escaping everywhere it appears.
    const NASTY_BACKEND: &str = "dual<&>\"'";
    /// A case name with every character class that needs care: markup, quotes, a control
    /// character XML forbids (U+0001), tab, newline, carriage return, non-ASCII.
    const NASTY_CASE: &str = "strips/thin<&\"'>\u{1}\ttab\nnl\rcr é";

    /// Every verdict, a case error, a no-contact case, nasty names and messages.
    fn report() -> SuiteReport {
        let backends = vec![
            "clarabel".to_string(),
            "osqp".to_string(),
            NASTY_BACKEND.to_string(),
        ];
        let mut fail = run("osqp", "inaccurate", 0.25, Verdict::Fail);
        fail.notes = vec![
            "objective -1.5 <differs> from \"expected\" & -1.4 by 7 %\u{0}".to_string(),
            "max |u| 0.3\tvs 0.2".to_string(),
        ];
        fail.message = Some("osqp says: <max iter> & 'bye'".to_string());
        let mut xpass = run("clarabel", "solved", 0.125, Verdict::UnexpectedPass);
        xpass.notes = vec!["expected \"max-iterations\"\r\nbut <solved>".to_string()];
        let mut unchecked = run("osqp", "error", f64::NAN, Verdict::Unchecked);
        unchecked.message = Some("cannot build: ]]> \u{1b}[31m".to_string());
        let mut broken = case("broken", Vec::new());
        broken.error = Some("cannot read suite/broken.toml: <bad> & \"key\"\u{7}\nline 2".into());
        let mut free = case(
            "free",
            vec![run("cholesky", "solved", 0.002, Verdict::Pass)],
        );
        free.constraints = 0;
        let cases = vec![
            case(
                "exp1",
                vec![
                    run("clarabel", "solved", 1.5, Verdict::Pass),
                    fail,
                    run(
                        NASTY_BACKEND,
                        "max-iterations",
                        2.0,
                        Verdict::ExpectedFailure,
                    ),
                ],
            ),
            case(
                NASTY_CASE,
                vec![
                    xpass,
                    unchecked,
                    run(NASTY_BACKEND, "solved", 0.5, Verdict::Pass),
                ],
            ),
            broken,
            free,
        ];
        sample::report("fixtures/<seed> & co", backends, cases, Some(30.0))
    }

    fn attr_usize(n: roxmltree::Node, a: &str) -> usize {
        n.attribute(a).unwrap().parse().unwrap()
    }

    fn child<'a, 'i>(n: roxmltree::Node<'a, 'i>, tag: &str) -> Option<roxmltree::Node<'a, 'i>> {
        n.children().find(|c| c.has_tag_name(tag))
    }

    fn elements<'a, 'i>(
        n: roxmltree::Node<'a, 'i>,
        tag: &'a str,
    ) -> impl Iterator<Item = roxmltree::Node<'a, 'i>> + 'a {
        n.children().filter(move |c| c.has_tag_name(tag))
    }

    #[test]
    fn counts_and_elements_match_an_independent_count_of_the_report() {
        let report = report();
        let xml = junit_xml(&report);
        let doc = roxmltree::Document::parse(&xml).unwrap();
        let root = doc.root_element();
        assert_eq!(root.tag_name().name(), "testsuites");
        assert_eq!(root.attribute("name"), Some("signorini suite"));

        // The suites: the backends, then `cholesky` for the no-contact case.
        let suites: Vec<_> = elements(root, "testsuite").collect();
        let names: Vec<&str> = suites
            .iter()
            .map(|s| s.attribute("name").unwrap())
            .collect();
        assert_eq!(names, ["clarabel", "osqp", NASTY_BACKEND, "cholesky"]);

        // Counted by hand from `report()`: (tests, failures, errors, skipped).
        let by_hand = [(3, 0, 1, 0), (3, 1, 1, 1), (3, 0, 1, 1), (1, 0, 0, 0)];
        let (mut tests, mut failures, mut errors) = (0, 0, 0);
        for (s, want) in suites.iter().zip(by_hand) {
            let name = s.attribute("name").unwrap();
            // An independent count straight from the report's runs.
            let runs = || {
                report
                    .cases
                    .iter()
                    .flat_map(|c| &c.runs)
                    .filter(|r| r.backend == name)
            };
            let n_err = if report.backends.iter().any(|b| b == name) {
                report.cases.iter().filter(|c| c.error.is_some()).count()
            } else {
                0
            };
            let counted = (
                runs().count() + n_err,
                runs().filter(|r| r.verdict == Verdict::Fail).count(),
                n_err,
                runs()
                    .filter(|r| matches!(r.verdict, Verdict::ExpectedFailure | Verdict::Unchecked))
                    .count(),
            );
            assert_eq!(
                counted, want,
                "{name}: the hand count disagrees with the report"
            );
            let got = (
                attr_usize(*s, "tests"),
                attr_usize(*s, "failures"),
                attr_usize(*s, "errors"),
                attr_usize(*s, "skipped"),
            );
            assert_eq!(got, want, "{name}");
            // The attributes agree with the elements.
            let cases: Vec<_> = elements(*s, "testcase").collect();
            assert_eq!(cases.len(), want.0);
            let with = |tag| cases.iter().filter(|c| child(**c, tag).is_some()).count();
            assert_eq!(
                (with("failure"), with("error"), with("skipped")),
                (want.1, want.2, want.3)
            );
            for c in &cases {
                assert_eq!(
                    c.attribute("classname").unwrap(),
                    format!("signorini.suite.{name}")
                );
            }
            // The suite's time is the sum of its cases' (NaN counted as 0), to the µs printed.
            let sum: f64 = runs().map(|r| r.solve_s).filter(|t| t.is_finite()).sum();
            let time: f64 = s.attribute("time").unwrap().parse().unwrap();
            assert!((time - sum).abs() < 1e-6, "{name}: {time} vs {sum}");
            tests += want.0;
            failures += want.1;
            errors += want.2;
        }
        assert_eq!(attr_usize(root, "tests"), tests);
        assert_eq!(attr_usize(root, "failures"), failures);
        assert_eq!(attr_usize(root, "errors"), errors);
        // 1.5 + 0.25 + 2 + 0.125 + 0.5 + 0.002 s, NaN as 0.
        let total: f64 = root.attribute("time").unwrap().parse().unwrap();
        assert!((total - 4.377).abs() < 1e-9, "{total}");
    }

    #[test]
    fn each_verdict_becomes_its_element() {
        let xml = junit_xml(&report());
        let doc = roxmltree::Document::parse(&xml).unwrap();
        let find = |suite: &str, case: &str| {
            doc.descendants()
                .find(|n| n.has_tag_name("testsuite") && n.attribute("name") == Some(suite))
                .and_then(|s| elements(s, "testcase").find(|c| c.attribute("name") == Some(case)))
                .unwrap_or_else(|| panic!("no test case {case} in {suite}"))
        };
        let nasty = xml_sanitize(NASTY_CASE);

        // pass: nothing inside.
        let pass = find("clarabel", "exp1");
        assert_eq!(pass.children().filter(|c| c.is_element()).count(), 0);
        assert_eq!(pass.attribute("time"), Some("1.500000"));

        // fail: the first note as message, every note, status and message in the text.
        let failure = child(find("osqp", "exp1"), "failure").unwrap();
        assert_eq!(failure.attribute("type"), Some("regression"));
        assert_eq!(
            failure.attribute("message").unwrap(),
            xml_sanitize("objective -1.5 <differs> from \"expected\" & -1.4 by 7 %\u{0}")
        );
        let text = failure.text().unwrap();
        assert!(text.contains("max |u| 0.3\tvs 0.2"), "{text}");
        assert!(text.contains("inaccurate"), "{text}");
        assert!(text.contains("osqp says: <max iter> & 'bye'"), "{text}");

        // expected failure: skipped, with the status.
        let skipped = child(find(NASTY_BACKEND, "exp1"), "skipped").unwrap();
        assert_eq!(
            skipped.attribute("message"),
            Some("expected failure: status max-iterations")
        );

        // unexpected pass: no failure/skipped/error, a system-out saying so, the note kept
        // (its carriage return too).
        let xpass = find("clarabel", &nasty);
        for tag in ["failure", "error", "skipped"] {
            assert!(child(xpass, tag).is_none(), "{tag}");
        }
        let out = child(xpass, "system-out").unwrap().text().unwrap();
        assert!(out.starts_with("unexpected pass"), "{out}");
        assert!(
            out.contains("expected \"max-iterations\"\r\nbut <solved>"),
            "{out:?}"
        );

        // unchecked: skipped, telling to bless; NaN time written as 0.
        let unchecked = find("osqp", &nasty);
        assert_eq!(unchecked.attribute("time"), Some("0.000000"));
        let skipped = child(unchecked, "skipped").unwrap();
        assert_eq!(
            skipped.attribute("message"),
            Some("no expectation: run with --bless")
        );
        assert!(skipped
            .text()
            .unwrap()
            .contains(&xml_sanitize("cannot build: ]]> \u{1b}[31m")));

        // The no-contact case is in the `cholesky` suite only.
        let free = find("cholesky", "free");
        assert_eq!(
            free.attribute("classname"),
            Some("signorini.suite.cholesky")
        );
        assert!(!xml.contains("name=\"free\" classname=\"signorini.suite.clarabel\""));
    }

    #[test]
    fn a_case_error_shows_in_every_backend() {
        let report = report();
        let xml = junit_xml(&report);
        let doc = roxmltree::Document::parse(&xml).unwrap();
        let error = report.cases[2].error.as_deref().unwrap();
        let mut seen = Vec::new();
        for suite in doc.descendants().filter(|n| n.has_tag_name("testsuite")) {
            for c in elements(suite, "testcase") {
                if let Some(e) = child(c, "error") {
                    assert_eq!(c.attribute("name"), Some("broken"));
                    assert_eq!(e.attribute("message").unwrap(), xml_sanitize(error));
                    assert_eq!(e.attribute("type"), Some("case-error"));
                    assert!(e.text().unwrap().contains(&xml_sanitize(error)));
                    seen.push(suite.attribute("name").unwrap().to_string());
                }
            }
        }
        assert_eq!(seen, report.backends);
    }

    #[test]
    fn escaping_round_trips() {
        let report = report();
        let xml = junit_xml(&report);
        // Characters XML 1.0 forbids are never written, not even as references.
        assert!(!xml.contains('\u{1}') && !xml.contains('\u{0}') && !xml.contains('\u{7}'));
        let doc = roxmltree::Document::parse(&xml).unwrap();
        // The nasty case name comes back exactly (tab, newline, carriage return, quotes,
        // markup), with only the forbidden U+0001 replaced.
        let names: Vec<&str> = doc
            .descendants()
            .filter(|n| n.has_tag_name("testcase"))
            .filter_map(|n| n.attribute("name"))
            .collect();
        let want = NASTY_CASE.replace('\u{1}', "\u{FFFD}");
        assert_eq!(names.iter().filter(|n| **n == want).count(), 3);
        // The nasty backend in suite name and classname.
        assert!(doc
            .descendants()
            .any(|n| n.has_tag_name("testsuite") && n.attribute("name") == Some(NASTY_BACKEND)));
        assert!(doc.descendants().any(|n| {
            n.attribute("classname") == Some(&format!("signorini.suite.{NASTY_BACKEND}")[..])
        }));
        // The properties: the suite dir and the tolerance.
        let props: Vec<(&str, &str)> = doc
            .descendants()
            .filter(|n| n.has_tag_name("property"))
            .take(3)
            .map(|n| (n.attribute("name").unwrap(), n.attribute("value").unwrap()))
            .collect();
        assert_eq!(
            props,
            [
                ("dir", "fixtures/<seed> & co"),
                ("tolerance", "1e-8"),
                ("time_limit_s", "30")
            ]
        );
    }

    /// The rules of the JUnit schema CI tools validate against (the Jenkins xunit plugin's
    /// `junit-10.xsd`, checked by hand against the document once, see the module's docs),
    /// written down: allowed elements and attributes, required attributes, the time pattern.
    #[test]
    fn the_document_follows_the_junit_schema_rules() {
        let r = report();
        // Also an empty suite: no case at all.
        let empty = SuiteReport {
            cases: Vec::new(),
            summary: Vec::new(),
            ..r.clone()
        };
        for report in [r, empty] {
            let xml = junit_xml(&report);
            assert!(xml.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"));
            let doc = roxmltree::Document::parse(&xml).unwrap();
            // junit-10.xsd's SUREFIRE_TIME, for what this writer produces: digits, a dot,
            // digits.
            let time_ok = |t: &str| {
                let (a, b) = t.split_once('.').unwrap_or((t, "0"));
                !a.is_empty()
                    && a.bytes().all(|c| c.is_ascii_digit())
                    && b.bytes().all(|c| c.is_ascii_digit())
            };
            for n in doc.descendants().filter(|n| n.is_element()) {
                let attrs: Vec<&str> = n.attributes().map(|a| a.name()).collect();
                let (allowed, required): (&[&str], &[&str]) = match n.tag_name().name() {
                    "testsuites" => (&["name", "time", "tests", "failures", "errors"], &[]),
                    "testsuite" => (
                        &["name", "tests", "failures", "errors", "skipped", "time"],
                        &["name", "tests", "failures", "errors", "time"],
                    ),
                    "properties" | "system-out" => (&[], &[]),
                    "property" => (&["name", "value"], &["name", "value"]),
                    "testcase" => (
                        &["name", "classname", "time"],
                        &["name", "classname", "time"],
                    ),
                    "failure" | "error" => (&["message", "type"], &["message", "type"]),
                    "skipped" => (&["message"], &["message"]),
                    other => panic!("element {other} is not in the schema"),
                };
                for a in &attrs {
                    assert!(allowed.contains(a), "{a} on {:?}", n.tag_name());
                }
                for a in required {
                    assert!(attrs.contains(a), "{a} missing on {:?}", n.tag_name());
                }
                if let Some(t) = n.attribute("time") {
                    assert!(time_ok(t), "{t}");
                    // SUREFIRE_TIME (testsuites, testsuite): at most three decimals.
                    if n.tag_name().name() != "testcase" {
                        let decimals = t.split_once('.').map_or(0, |(_, b)| b.len());
                        assert!(decimals <= 3, "{t} on {:?}", n.tag_name());
                    }
                }
                // Where each element may sit.
                let parent = n.parent_element().map(|p| p.tag_name().name());
                let want_parent = match n.tag_name().name() {
                    "testsuites" => None,
                    "testsuite" => Some("testsuites"),
                    "properties" | "testcase" => Some("testsuite"),
                    "property" => Some("properties"),
                    _ => Some("testcase"),
                };
                assert_eq!(parent, want_parent, "{:?}", n.tag_name());
            }
        }
    }

    #[test]
    fn no_backend_still_reports_case_errors() {
        let mut r = report();
        r.backends.clear();
        r.cases.retain(|c| c.error.is_some());
        let doc_xml = junit_xml(&r);
        let doc = roxmltree::Document::parse(&doc_xml).unwrap();
        let root = doc.root_element();
        assert_eq!(attr_usize(root, "errors"), 1);
        assert_eq!(attr_usize(root, "tests"), 1);
    }
}
