//! `signorini suite`: a directory of scenes through every backend, checked against their expectations.

use std::path::PathBuf;

use anyhow::{Context, Result};
use signorini::backends::{BackendKind, ChoiceParser};
use signorini::exit::Exit;
use signorini::suite::{self, bless::Blessing, bless::Change, report::SuiteReport};
use signorini_core::mesh::MeshLimits;
use signorini_core::qp::SolveOptions;

use crate::args::{parse_backends, parse_factor, parse_time_limit, parse_tol, time_limit};
use crate::console::{warn, Console};

/// `signorini suite DIR …`: the options of a suite run.
#[derive(clap::Args)]
pub(crate) struct SuiteArgs {
    /// Directory of scenes (*.toml, searched recursively), each with NAME.expected.json beside
    /// it (e.g. fixtures/seed, fixtures/hard).
    pub(crate) dir: PathBuf,
    /// Comma-separated backends [default: every one compiled in: clarabel, osqp, dual-pgs,
    /// dual-uzawa, dual-ssn, pdas].
    #[arg(long, value_delimiter = ',', value_parser = ChoiceParser::<BackendKind>::new())]
    pub(crate) backends: Vec<BackendKind>,
    /// Relative KKT tolerance every backend is asked to meet (the expectations were blessed at
    /// 1e-9: a looser tolerance may move answers beyond their rtol).
    #[arg(long, default_value_t = 1e-9, value_parser = parse_tol)]
    pub(crate) tol: f64,
    /// Seconds each backend may take on each case; it then stops with status time-limit (a
    /// failure, counted at this time in the shifted geometric means).
    #[arg(long, default_value_t = 10.0, value_parser = parse_time_limit)]
    pub(crate) time_limit: f64,
    /// Solves timed per backend and case; the median is reported.  Only solves that succeed in
    /// under a second are repeated (longer ones are not dominated by timer noise).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
    pub(crate) repeat: u32,
    /// Run only the cases whose name contains one of these texts (comma-separated), e.g.
    /// `--only strip,contrast`.
    #[arg(long, value_delimiter = ',')]
    pub(crate) only: Vec<String>,
    /// Largest total number of elements a scene may ask for before it is refused.
    #[arg(long, default_value_t = 5_000_000)]
    pub(crate) max_elements: usize,
    /// Write or refresh every case's expectation from the most accurate backend that solved it
    /// (tolerances and reasons of existing files kept; only changed files rewritten).
    #[arg(long)]
    pub(crate) bless: bool,
    /// An earlier run's suite.json: report which cases got slower or faster (time ÷ floor) or
    /// changed status.
    #[arg(long, value_name = "SUITE_JSON")]
    pub(crate) baseline: Option<PathBuf>,
    /// With --baseline: the factor of time ÷ floor beyond which a case is slower or faster.
    #[arg(long, default_value_t = signorini::suite::baseline::DEFAULT_FACTOR, value_parser = parse_factor, requires = "baseline")]
    pub(crate) factor: f64,
    /// With --baseline: exit 2 when a case got slower (by default slower cases are reported only).
    #[arg(long, requires = "baseline")]
    pub(crate) fail_slower: bool,
    /// Output directory for suite.json, suite.csv, suite.xml and suite.svg (created if missing).
    #[arg(long, default_value = "out")]
    pub(crate) out: PathBuf,
}

pub(crate) fn suite(args: &SuiteArgs) -> Result<Exit> {
    let settings = settings(args)?;
    // A bad baseline is refused before anything runs.
    let baseline = args
        .baseline
        .as_deref()
        .map(suite::baseline::Baseline::read)
        .transpose()?;
    let bar = indicatif::ProgressBar::new(0).with_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} cases  {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let mut report = suite::run(&args.dir, &settings, |step| {
        bar.set_length(step.cases as u64);
        bar.set_position(step.case as u64);
        bar.set_message(format!("{}: {}", step.name, step.what));
    })?;
    bar.finish_and_clear();
    let settings_report = signorini_core::report::BackendSettings {
        backend: report.backends.join(","),
        form: signorini::contract::forms(&settings.backends),
        tolerance: settings.solve.tol,
        time_limit_s: settings.solve.time_limit.map(|t| t.as_secs_f64()),
        max_iter: settings.solve.max_iter,
        chain: Vec::new(),
        coulomb: signorini_core::qp::CoulombMethod::Auto,
    };
    // The suite's scenes are many: each case records its own file's hash, and the suite's is
    // that of the list of cases with theirs.
    report.provenance = Some(signorini::contract::provenance_of(
        Some(args.dir.display().to_string()),
        suite::suite_sha256(&report.cases),
        settings_report,
    ));
    if let Some(baseline) = &baseline {
        report.baseline = Some(suite::baseline::compare(&report, baseline, args.factor));
    }
    let mut blessed = Vec::new();
    if args.bless {
        blessed = suite::bless::blessings(&report)?;
        suite::bless::write(&blessed).context("writing the expectations")?;
    }
    let written = suite::write::write(&args.out, &report)
        .with_context(|| format!("writing the suite's files to {}", args.out.display()))?;
    print_summary(args, &report, &blessed, &written)?;
    Ok(verdict(args, &report))
}

/// The suite's settings from the command line: the backends named (or every default one
/// compiled in), the solve options, the element limit, repetitions and the cases selected.
fn settings(args: &SuiteArgs) -> Result<suite::SuiteSettings> {
    let backends = if args.backends.is_empty() {
        suite::DEFAULT_BACKENDS
            .into_iter()
            .filter(|k| k.available())
            .collect()
    } else {
        parse_backends(&args.backends, &[])?
    };
    Ok(suite::SuiteSettings {
        backends,
        solve: SolveOptions {
            tol: args.tol,
            time_limit: time_limit(Some(args.time_limit)),
            ..SolveOptions::default()
        },
        limits: MeshLimits {
            max_elements: args.max_elements,
            ..MeshLimits::default()
        },
        repeat: args.repeat as usize,
        only: args.only.clone(),
    })
}

/// Prints the table, the comparison with the baseline, the blessings and the files written.
fn print_summary(
    args: &SuiteArgs,
    report: &SuiteReport,
    blessed: &[Blessing],
    written: &[PathBuf],
) -> Result<()> {
    let mut con = Console::new();
    for line in suite::table::table(report).lines() {
        con.line(line)?;
    }
    if let Some(b) = &report.baseline {
        con.line("")?;
        for line in suite::baseline::text(b, report.tolerance).lines() {
            con.line(line)?;
        }
    }
    if args.bless {
        con.line("")?;
        print_blessings(&mut con, blessed)?;
    }
    for p in written {
        con.line(format_args!("  wrote {}", p.display()))?;
    }
    con.finish()?;
    Ok(())
}

/// One line per blessed (or skipped) expectation, then the count of unchanged ones.
fn print_blessings(con: &mut Console, blessed: &[Blessing]) -> Result<()> {
    for b in blessed {
        let path = b.path.display();
        match &b.change {
            Change::New => con.line(format_args!("  blessed {path} (new)"))?,
            Change::Changed(what) => {
                con.line(format_args!("  blessed {path} (changed):"))?;
                for w in what {
                    con.line(format_args!("      {w}"))?;
                }
            }
            Change::Unchanged => {}
            Change::Skipped(why) => con.line(format_args!("  not blessed {}: {why}", b.case))?,
        }
    }
    let unchanged = blessed
        .iter()
        .filter(|b| b.change == Change::Unchanged)
        .count();
    con.line(format_args!(
        "  {unchanged} expectations unchanged (within their tolerances)"
    ))?;
    Ok(())
}

/// The exit code, with a warning for each reason it is not 0: with `--bless`, cases that could
/// not run; else regressions, cases without an expectation and (with `--fail-slower`) slower
/// runs.
fn verdict(args: &SuiteArgs, report: &SuiteReport) -> Exit {
    let errors: Vec<&str> = report
        .cases
        .iter()
        .filter(|c| c.error.is_some())
        .map(|c| c.name.as_str())
        .collect();
    if args.bless {
        if errors.is_empty() {
            return Exit::Success;
        }
        warn(format_args!(
            "error: could not run, so not blessed: {}",
            errors.join(", ")
        ));
        return Exit::NotSolved;
    }
    let regressed = report.regressions();
    let unchecked: Vec<&str> = report
        .cases
        .iter()
        .filter(|c| c.error.is_none() && c.expectation.is_none())
        .map(|c| c.name.as_str())
        .collect();
    let slower = report.baseline.as_ref().map_or(0, |b| b.slower());
    let mut code = Exit::Success;
    if !regressed.is_empty() {
        warn(format_args!("error: regressed: {}", regressed.join(", ")));
        code = Exit::NotSolved;
    }
    if !unchecked.is_empty() {
        warn(format_args!(
            "error: no expectation, nothing checked (run with --bless): {}",
            unchecked.join(", ")
        ));
        code = Exit::NotSolved;
    }
    if args.fail_slower && slower > 0 {
        warn(format_args!(
            "error: {slower} runs slower than the baseline by more than {}×",
            args.factor
        ));
        code = Exit::NotSolved;
    }
    code
}
