//! The suite as text on the terminal: a case × backend grid, what broke, a summary per backend.
//!
//! A cell is `✓ 3.2` (passed, time ÷ floor), `✗ objective` or `✗ inaccurate` (a regression:
//! the first figure that broke, or the status when it did not solve), `(✗) inaccurate` (an
//! expected failure), `✓! 3.2` (an unexpected pass), `? 3.2` (no expectation to check).

use super::report::{CaseReport, CaseRun, SuiteReport, Verdict};

/// Width of a backend column.
const CELL: usize = 17;

/// The figure a note is about: its text before `: ` (`objective`, `max |u|`, `pair 1 (a–b)
/// normal force`, `probe "tip" ux`), or the whole note.
fn figure_of(note: &str) -> &str {
    note.split_once(": ").map_or(note, |(head, _)| head)
}

/// `s` cut to `width` characters (with `…` when cut).
fn fit(s: &str, width: usize) -> String {
    if s.chars().count() <= width {
        s.to_string()
    } else {
        let mut t: String = s.chars().take(width.saturating_sub(1)).collect();
        t.push('…');
        t
    }
}

/// A run's cell.
pub fn cell(run: &CaseRun) -> String {
    let ratio = || {
        if run.ratio_to_floor.is_finite() {
            format!("{:.1}", run.ratio_to_floor)
        } else {
            "-".to_string()
        }
    };
    let text = match run.verdict {
        Verdict::Pass if run.status == "solved" => format!("✓ {}", ratio()),
        // A scene without a solution, rightly not solved.
        Verdict::Pass => format!("✓ {}", run.status),
        Verdict::UnexpectedPass => format!("✓! {}", ratio()),
        Verdict::ExpectedFailure => format!("(✗) {}", run.status),
        Verdict::Fail if run.status != "solved" => format!("✗ {}", run.status),
        Verdict::Fail => format!("✗ {}", run.notes.first().map_or("", |n| figure_of(n))),
        Verdict::Unchecked if run.status == "solved" => format!("? {}", ratio()),
        Verdict::Unchecked => format!("? {}", run.status),
    };
    fit(&text, CELL)
}

fn row(case: &CaseReport, backends: &[String], name_width: usize) -> String {
    let mut line = format!("  {:<name_width$}", case.name);
    if let Some(error) = &case.error {
        // The first line only (a TOML error quotes the file below it); the details list has all.
        let first = error.lines().next().unwrap_or("");
        line.push_str(&format!(" ✗ error: {first}"));
        return line;
    }
    if let [only] = case.runs.as_slice() {
        if only.backend == "cholesky" {
            line.push_str(&format!(
                " {:<CELL$} (no contact row: one linear solve)",
                cell(only)
            ));
            return line;
        }
    }
    for backend in backends {
        let text = case
            .runs
            .iter()
            .find(|r| &r.backend == backend)
            .map_or(String::new(), cell);
        line.push_str(&format!(" {text:<CELL$}"));
    }
    line.trim_end().to_string()
}

/// The whole text: the grid, the details of every regression, unexpected pass and missing
/// expectation, and the per-backend summary.
pub fn table(report: &SuiteReport) -> String {
    let name_width = report
        .cases
        .iter()
        .map(|c| c.name.chars().count())
        .max()
        .unwrap_or(4)
        .max(4);
    let mut t = format!(
        "suite {}: {} cases × {} backends, tol {:e}, time limit {}\n",
        report.dir,
        report.cases.len(),
        report.backends.len(),
        report.tolerance,
        report
            .time_limit_s
            .map_or("none".to_string(), |s| format!("{s} s"))
    );
    t.push_str(&format!("  {:<name_width$}", "case"));
    for b in &report.backends {
        t.push_str(&format!(" {:<CELL$}", fit(b, CELL)));
    }
    t = t.trim_end().to_string();
    t.push('\n');
    for case in &report.cases {
        t.push_str(&row(case, &report.backends, name_width));
        t.push('\n');
    }
    t.push_str("  ✓ pass (time ÷ floor)  ✗ regression  (✗) expected failure  ✓! unexpected pass  ? no expectation\n");
    let mut details = Vec::new();
    let mut unchecked = Vec::new();
    for case in &report.cases {
        if let Some(e) = &case.error {
            details.push(format!("  ✗ {}: {e}", case.name));
        }
        if case.error.is_none() && case.expectation.is_none() {
            unchecked.push(case.name.as_str());
        }
        for run in &case.runs {
            let mark = match run.verdict {
                Verdict::Fail => "✗",
                Verdict::UnexpectedPass => "✓!",
                Verdict::ExpectedFailure if !run.notes.is_empty() => "(✗)",
                _ => continue,
            };
            for note in &run.notes {
                details.push(format!("  {mark} {} / {}: {note}", case.name, run.backend));
            }
            if run.verdict == Verdict::Fail {
                if let Some(m) = &run.message {
                    details.push(format!("      {}: {m}", run.backend));
                }
            }
        }
    }
    if !details.is_empty() {
        t.push('\n');
        for d in details {
            t.push_str(&d);
            t.push('\n');
        }
    }
    if !unchecked.is_empty() {
        t.push_str(&format!(
            "\n  no expectation (nothing checked; write them with --bless): {}\n",
            unchecked.join(", ")
        ));
    }
    t.push_str(&format!(
        "\n  {:<12} {:>7} {:>9} {:>8} {:>9} {:>12} {:>10} {:>9}\n",
        "backend",
        "success",
        "regress.",
        "exp.fail",
        "unexp.ok",
        "sgm time ms",
        "×best",
        "sgm ÷floor"
    ));
    for s in &report.summary {
        t.push_str(&format!(
            "  {:<12} {:>6.0}% {:>9} {:>8} {:>9} {:>12.3} {:>10.2} {:>9.2}\n",
            fit(&s.backend, 12),
            100.0 * s.success_rate,
            s.regressions,
            s.expected_failures,
            s.unexpected_passes,
            1e3 * s.sgm_time_s,
            s.sgm_time_relative,
            s.sgm_ratio
        ));
    }
    t.push_str("  (shifted geometric means: time shifted by 10 ms, time ÷ floor by 1; a case not answered correctly counts at the time limit)\n");
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_broken_figure_is_named_in_its_cell() {
        assert_eq!(
            figure_of("objective: -1.2e-5, expected -1.3e-5 (difference …)"),
            "objective"
        );
        assert_eq!(figure_of("max |u|: 1.0e0, expected 2.0e0"), "max |u|");
        assert_eq!(
            figure_of("pair 1 (upper–lower) normal force: 3e-5, expected"),
            "pair 1 (upper–lower) normal force"
        );
        assert_eq!(fit("abcdef", 4), "abc…");
        assert_eq!(fit("abc", 4), "abc");
    }
}
