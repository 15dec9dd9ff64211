//! `signorini`: frictionless contact of elastic bodies in 2D, solved by several QP backends.
//!
//! Exit codes (see `docs/scene.md`): 0 solved or valid, 1 bad input or usage, 2 not solved,
//! 3 I/O or resource error.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use signorini::auto::AutoBackend;
use signorini::backends::{make_backend, BackendKind, ChoiceParser, Form, NamedParser};
use signorini::exit::{classify, Exit};
use signorini::run;
use signorini_core::mesh::MeshLimits;
use signorini_core::qp::{QpStatus, SolveOptions};

#[derive(Parser)]
#[command(
    name = "signorini",
    version,
    about = "2D frictionless contact of elastic bodies by FEM, through several QP backends",
    after_help = "Exit codes: 0 solved (or valid), 1 bad input or usage, 2 not solved, 3 I/O or resource error.\nThe scene and result formats: docs/scene.md."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Args)]
struct Common {
    /// Scene file (TOML, see docs/scene.md); the seed's Experiment 2b when omitted.
    scene: Option<PathBuf>,
    /// Largest total number of elements (all bodies) a scene may ask for before it is refused.
    #[arg(long, default_value_t = 5_000_000)]
    max_elements: usize,
}

/// Seconds a backend may take: positive; values from 1e9 s (31 years) up mean no limit.
fn parse_time_limit(text: &str) -> Result<f64, String> {
    let t: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number of seconds"))?;
    if t.is_finite() && t > 0.0 || t == f64::INFINITY {
        Ok(t)
    } else {
        Err(format!("must be a positive number of seconds, got {text}"))
    }
}

/// The limit as a duration; `None` (no limit) for 1e9 s and more, where a `Duration` would be of
/// no use (and `Duration::from_secs_f64` panics beyond its range).
fn time_limit(seconds: Option<f64>) -> Option<Duration> {
    seconds
        .filter(|t| *t < 1e9)
        .and_then(|t| Duration::try_from_secs_f64(t).ok())
}

/// A tolerance in (0, 1).
fn parse_tol(text: &str) -> Result<f64, String> {
    let t: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number"))?;
    if t.is_finite() && t > 0.0 && t < 1.0 {
        Ok(t)
    } else {
        Err(format!("must lie in (0, 1), got {text}"))
    }
}

#[derive(Subcommand)]
enum Command {
    /// Mesh, assemble and solve a scene; write result.json, solution.vtu, deformed.svg and, when
    /// the scene has contact rows, pressure.svg.
    Solve {
        #[command(flatten)]
        common: Common,
        /// QP backend: auto is the fastest likely to succeed, falling back to a robust one (see
        /// docs/scene.md); clarabel/dual and osqp/dual are the condensed dual form.
        #[arg(long, default_value = "auto", value_parser = ChoiceParser::<BackendKind>::new())]
        backend: BackendKind,
        /// Formulation for clarabel and osqp: primal (sparse, in the displacements) or dual
        /// (condensed, dense in the contact forces; not for bodies held by contact alone).
        /// `--backend clarabel --form dual` is `--backend clarabel/dual`.
        #[arg(long, value_parser = ChoiceParser::<Form>::new())]
        form: Option<Form>,
        /// With `--backend auto`: the backends to try, in order, instead of auto's rule
        /// (e.g. dual-ssn,clarabel).
        #[arg(long, value_delimiter = ',', value_parser = ChoiceParser::<BackendKind>::new())]
        chain: Vec<BackendKind>,
        /// Relative KKT tolerance the answer must meet to count as solved.
        #[arg(long, default_value_t = 1e-9, value_parser = parse_tol)]
        tol: f64,
        /// Seconds the backend may take (with auto: the whole chain); it then stops with status
        /// time-limit.
        #[arg(long, value_parser = parse_time_limit)]
        time_limit: Option<f64>,
        /// Output directory (created if missing).
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Encoding of solution.vtu: binary (zlib-compressed, base64 appended data; small and
        /// fast to read) or ascii (decimal text, several times larger).
        #[arg(long, value_enum, default_value_t = signorini::output::VtuFormat::Binary)]
        vtu: signorini::output::VtuFormat,
    },
    /// Mesh and assemble once, then solve the same QP with several backends and compare them.
    Compare {
        #[command(flatten)]
        common: Common,
        /// Comma-separated backends [default: clarabel,osqp,dual-pgs,dual-uzawa, those compiled in].
        #[arg(long, value_delimiter = ',', value_parser = ChoiceParser::<BackendKind>::new())]
        backends: Vec<BackendKind>,
        /// Comma-separated forms each of clarabel and osqp runs in; the other backends run
        /// once, in their own form [default: as named in --backends].
        #[arg(long, value_delimiter = ',', value_parser = ChoiceParser::<Form>::new())]
        forms: Vec<Form>,
        /// Relative KKT tolerance every backend is asked to meet.
        #[arg(long, default_value_t = 1e-9, value_parser = parse_tol)]
        tol: f64,
        /// Seconds each backend may take; it then stops with status time-limit.
        #[arg(long, value_parser = parse_time_limit)]
        time_limit: Option<f64>,
        /// Output directory for compare.json and compare.csv (created if missing).
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Instead of a scene: a directory holding a QP as Matrix Market files A.mtx, f.mtx,
        /// B.mtx, g.mtx (the layout `export` writes; docs/scene.md), from this or another code.
        #[arg(long, value_name = "DIR", conflicts_with_all = ["scene", "max_elements"])]
        qp: Option<PathBuf>,
    },
    /// Refine the mesh and time every backend and tolerance; write sweep.csv and plots.
    /// `sweep merge DIR…` joins the shards of a sweep run with `--shard I/N`.
    #[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
    Sweep {
        #[command(flatten)]
        args: SweepArgs,
        #[command(subcommand)]
        action: Option<SweepAction>,
    },
    /// Discretisation error against time for a scene with a [reference]: every formulation ×
    /// mesh kind × element and mesh size; write study.csv and accuracy.svg.
    Study {
        #[command(flatten)]
        common: Common,
        /// Comma-separated sizes of the coarsest body, e.g. 0.04,0.02,0.01; every other size of
        /// the scene (other bodies, [[body.refine]]) is scaled by the same factor.
        #[arg(long, value_delimiter = ',', required = true)]
        hmax: Vec<f64>,
        /// Comma-separated contact formulations set on every pair.
        #[arg(long, value_delimiter = ',', default_value = "node-to-segment,mortar", value_parser = NamedParser::new(&["node-to-segment", "mortar"], signorini::study::parse_formulation))]
        formulations: Vec<signorini_core::scene::Formulation>,
        /// Comma-separated mesh kinds: uniform (every [[body.refine]] dropped), graded (kept).
        #[arg(long, value_delimiter = ',', default_value = "uniform,graded", value_parser = NamedParser::new(&["uniform", "graded"], |s| s.parse::<signorini::study::MeshKind>()))]
        meshes: Vec<signorini::study::MeshKind>,
        /// Comma-separated elements set on the bodies that are axis-aligned rectangles.
        #[arg(long, value_delimiter = ',', default_value = "p1,q1", value_parser = NamedParser::new(&["p1", "q1"], signorini::study::parse_element))]
        elements: Vec<signorini_core::mesh::ElementKind>,
        /// QP backend every point is solved with (as for solve).
        #[arg(long, default_value = "auto", value_parser = ChoiceParser::<BackendKind>::new())]
        backend: BackendKind,
        /// Relative KKT tolerance every point must meet to count as solved.
        #[arg(long, default_value_t = 1e-9, value_parser = parse_tol)]
        tol: f64,
        /// Replace an existing DIR/study.csv (without it, an existing file is refused).
        #[arg(long)]
        overwrite: bool,
        /// Output directory for study.csv and accuracy.svg (created if missing).
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
    /// Run every scene of a directory (recursively) through every backend and check each answer
    /// against the scene's stored expectation NAME.expected.json; write suite.json, suite.csv,
    /// suite.xml (JUnit) and suite.svg (performance profile).  Exit 2 when a case regressed.
    Suite(SuiteArgs),
    /// Write the scene's QP (A, f, B, g as Matrix Market) and its DOF and row maps.
    Export {
        #[command(flatten)]
        common: Common,
        /// Output directory (created if missing).
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
    /// Validate a scene exactly as solve does (parse, estimate, mesh, assemble), without solving.
    Check {
        #[command(flatten)]
        common: Common,
    },
    /// Print the JSON Schema (draft 2020-12) of the scene file, result.json, a suite's
    /// NAME.expected.json or suite.json, generated from the program's own types (see
    /// docs/scene.md).
    Schema {
        /// Which document.
        #[arg(value_enum)]
        document: signorini::contract::Document,
    },
}

/// `signorini sweep SCENE …`: the options of a sweep.
#[derive(clap::Args)]
struct SweepArgs {
    #[command(flatten)]
    common: Common,
    /// Comma-separated mesh sizes, e.g. 0.2,0.1,0.05.
    #[arg(long, value_delimiter = ',', required = true)]
    hmax: Vec<f64>,
    /// Comma-separated bodies whose hmax is swept (default: all).
    #[arg(long, value_delimiter = ',')]
    bodies: Vec<String>,
    /// Comma-separated backends [default: clarabel,osqp,dual-pgs,dual-uzawa, those compiled in].
    #[arg(long, value_delimiter = ',', value_parser = ChoiceParser::<BackendKind>::new())]
    backends: Vec<BackendKind>,
    /// Comma-separated tolerances.
    #[arg(long, value_delimiter = ',', default_value = "1e-9", value_parser = parse_tol)]
    tol: Vec<f64>,
    /// Runs per point (medians are reported); at least 1.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    repeat: u32,
    /// Seconds one solve may take; a backend that exceeds it is skipped on finer meshes.
    #[arg(long, value_parser = parse_time_limit)]
    time_limit: Option<f64>,
    /// Keep the points already in DIR/sweep.csv (verified to be this scene's and this grid's)
    /// and run only the missing ones.
    #[arg(long)]
    resume: bool,
    /// Replace an existing DIR/sweep.csv (without this or --resume, an existing file is
    /// refused); it is replaced once the new sweep writes its first point.  Excludes --resume.
    #[arg(long)]
    overwrite: bool,
    /// Run only shard I of N: the plan's points I, I+N, I+2N, … (numbered from 1, hmax coarse to
    /// fine, then tolerances tightest first, then backends); join the N directories with
    /// `signorini sweep merge`.
    #[arg(long, value_name = "I/N", value_parser = parse_shard)]
    shard: Option<signorini::sweep::shard::Shard>,
    /// Also write each point's solution as DIR/solutions/<point>.vtu and the ParaView
    /// collection DIR/solutions.pvd (timestep = the point's number in the plan).
    #[arg(long)]
    vtu: bool,
    /// Output directory for sweep.csv and the plots (created if missing).
    #[arg(long, default_value = "out")]
    out: PathBuf,
}

/// `signorini suite DIR …`: the options of a suite run.
#[derive(clap::Args)]
struct SuiteArgs {
    /// Directory of scenes (*.toml, searched recursively), each with NAME.expected.json beside
    /// it (e.g. fixtures/seed, fixtures/hard).
    dir: PathBuf,
    /// Comma-separated backends [default: every one compiled in: clarabel, osqp, dual-pgs,
    /// dual-uzawa, dual-ssn, pdas].
    #[arg(long, value_delimiter = ',', value_parser = ChoiceParser::<BackendKind>::new())]
    backends: Vec<BackendKind>,
    /// Relative KKT tolerance every backend is asked to meet (the expectations were blessed at
    /// 1e-9: a looser tolerance may move answers beyond their rtol).
    #[arg(long, default_value_t = 1e-9, value_parser = parse_tol)]
    tol: f64,
    /// Seconds each backend may take on each case; it then stops with status time-limit (a
    /// failure, counted at this time in the shifted geometric means).
    #[arg(long, default_value_t = 10.0, value_parser = parse_time_limit)]
    time_limit: f64,
    /// Solves timed per backend and case; the median is reported.  Only solves that succeed in
    /// under a second are repeated (longer ones are not dominated by timer noise).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
    repeat: u32,
    /// Largest total number of elements a scene may ask for before it is refused.
    #[arg(long, default_value_t = 5_000_000)]
    max_elements: usize,
    /// Write or refresh every case's expectation from the most accurate backend that solved it
    /// (tolerances and reasons of existing files kept; only changed files rewritten).
    #[arg(long)]
    bless: bool,
    /// An earlier run's suite.json: report which cases got slower or faster (time ÷ floor) or
    /// changed status.
    #[arg(long, value_name = "SUITE_JSON")]
    baseline: Option<PathBuf>,
    /// With --baseline: the factor of time ÷ floor beyond which a case is slower or faster.
    #[arg(long, default_value_t = signorini::suite::baseline::DEFAULT_FACTOR, value_parser = parse_factor, requires = "baseline")]
    factor: f64,
    /// With --baseline: exit 2 when a case got slower (by default slower cases are reported only).
    #[arg(long, requires = "baseline")]
    fail_slower: bool,
    /// Output directory for suite.json, suite.csv, suite.xml and suite.svg (created if missing).
    #[arg(long, default_value = "out")]
    out: PathBuf,
}

/// A factor > 1.
fn parse_factor(text: &str) -> Result<f64, String> {
    let f: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number"))?;
    if f.is_finite() && f > 1.0 {
        Ok(f)
    } else {
        Err(format!("must be a number above 1, got {text}"))
    }
}

/// `I/N` with 1 ≤ I ≤ N.
fn parse_shard(text: &str) -> Result<signorini::sweep::shard::Shard, String> {
    text.parse()
}

#[derive(Subcommand)]
enum SweepAction {
    /// Check that the directories hold the shards 1/N … N/N of one sweep (same scene hash,
    /// grid, backends, tolerances; each shard once, complete) and merge them into one
    /// sweep.csv and its plots, computing the error columns over all points.
    Merge {
        /// The shards' output directories.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Replace an existing OUT/sweep.csv (without it, an existing file is refused).
        #[arg(long)]
        overwrite: bool,
        /// Output directory for the merged sweep.csv and plots (created if missing).
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
}

fn limits(common: &Common) -> MeshLimits {
    MeshLimits {
        max_elements: common.max_elements,
        ..MeshLimits::default()
    }
}

/// Standard output with write errors turned into errors (a closed pipe or a full disk is a clean
/// failure with exit code 3, never a panic as `println!` would give).
struct Console(std::io::Stdout);

impl Console {
    fn new() -> Self {
        Console(std::io::stdout())
    }

    fn line(&mut self, text: impl std::fmt::Display) -> Result<()> {
        writeln!(self.0, "{text}").context("writing to standard output")
    }

    fn finish(mut self) -> Result<()> {
        self.0.flush().context("writing to standard output")
    }
}

/// Prints to standard error, ignoring failure: there is nowhere left to report it.
fn warn(text: impl std::fmt::Display) {
    let _ = writeln!(std::io::stderr(), "{text}");
}

/// What `solve` was asked to run.
struct SolveArgs<'a> {
    backend: BackendKind,
    form: Option<Form>,
    chain: &'a [BackendKind],
    tol: f64,
    time_limit_s: Option<f64>,
    /// Encoding of solution.vtu.
    vtu: signorini::output::VtuFormat,
}

fn solve(common: &Common, args: &SolveArgs, out: &std::path::Path) -> Result<Exit> {
    let mut kind = args.backend;
    if let Some(form) = args.form {
        kind = kind.with_form(form)?;
    }
    anyhow::ensure!(
        kind.available(),
        "backend \"{kind}\" is not compiled in; rebuild with `--features osqp`"
    );
    anyhow::ensure!(
        args.chain.is_empty() || kind == BackendKind::Auto,
        "--chain is for --backend auto, not {kind}"
    );
    let scene = run::load_scene(common.scene.as_deref())?;
    let options = SolveOptions {
        tol: args.tol,
        time_limit: time_limit(args.time_limit_s),
        ..SolveOptions::default()
    };
    let settings = signorini_core::report::BackendSettings {
        backend: kind.name().to_string(),
        form: kind.form().name().to_string(),
        tolerance: options.tol,
        time_limit_s: options.time_limit.map(|t| t.as_secs_f64()),
        max_iter: options.max_iter,
        chain: args.chain.iter().map(|k| k.name().to_string()).collect(),
    };
    let provenance = signorini::contract::provenance(common.scene.as_deref(), settings)?;
    let mut outcome = if kind == BackendKind::Auto {
        let mut auto = if args.chain.is_empty() {
            AutoBackend::default()
        } else {
            let kinds = parse_backends(args.chain, &[])?;
            anyhow::ensure!(
                !kinds.contains(&BackendKind::Auto),
                "--chain cannot hold auto itself"
            );
            AutoBackend::with_kinds(kinds, "the chain given by --chain")
        };
        let result = run::solve_scene(&scene, &mut auto, &options, &limits(common));
        if let Some(record) = auto.record() {
            for attempt in &record.attempts {
                warn(attempt.line());
            }
            warn(format_args!(
                "auto: chose {}: {}",
                record.chosen.as_deref().unwrap_or("none"),
                record.reason
            ));
        }
        let mut outcome = result?;
        if let Some(record) = auto.record() {
            record.annotate(&mut outcome.report);
        }
        outcome
    } else {
        let mut backend = make_backend(kind)?;
        run::solve_scene(&scene, backend.as_mut(), &options, &limits(common))?
    };
    outcome.report.provenance = Some(provenance);
    let written = run::write_outputs_with(out, &scene, &outcome, args.vtu)
        .with_context(|| format!("writing results to {}", out.display()))?;
    let r = &outcome.report;
    let mut con = Console::new();
    con.line(&r.scene)?;
    con.line(format_args!(
        "  {} DOFs, {} contact rows ({} active); backend {}: {} in {} iterations",
        r.dofs, r.constraints, r.active_constraints, r.backend, r.status, r.iterations
    ))?;
    for b in &r.bodies {
        con.line(format_args!(
            "  body {:<10} {:>7} nodes {:>7} elements  max |u| = {:.6e}  reaction = [{:.4e}, {:.4e}]",
            b.name, b.nodes, b.elements, b.max_displacement, b.reaction[0], b.reaction[1]
        ))?;
    }
    for c in &r.contacts {
        if c.constraints > 0 {
            con.line(format_args!(
                "  contact {} – {} (slave {}): normal force {:.6e}",
                c.bodies[0], c.bodies[1], c.slave, c.normal_force
            ))?;
        }
    }
    con.line(format_args!(
        "  residuals: penetration {:.2e}, stationarity {:.2e}, complementarity {:.2e}, min multiplier {:.2e}",
        r.residuals.max_penetration,
        r.residuals.stationarity,
        r.residuals.complementarity,
        r.residuals.min_multiplier
    ))?;
    con.line(format_args!(
        "  time: mesh {:.4} s, assemble {:.4} s, solve {:.4} s, total {:.4} s",
        r.timing_s.mesh, r.timing_s.assemble, r.timing_s.solve, r.timing_s.total
    ))?;
    for p in &written {
        con.line(format_args!("  wrote {}", p.display()))?;
    }
    con.finish()?;
    for w in &r.warnings {
        warn(format_args!("warning: {}", w.message));
    }
    if outcome.solution.status == QpStatus::Solved {
        Ok(Exit::Success)
    } else {
        warn(format_args!(
            "error: status {} (backend said {}){}",
            outcome.solution.status,
            outcome.solution.backend_status,
            outcome
                .solution
                .message
                .as_deref()
                .map(|m| format!(": {m}"))
                .unwrap_or_default()
        ));
        Ok(Exit::NotSolved)
    }
}

fn compare(
    common: &Common,
    names: &[BackendKind],
    forms: &[Form],
    tol: f64,
    time_limit_s: Option<f64>,
    out: &std::path::Path,
    qp: Option<&std::path::Path>,
) -> Result<Exit> {
    let kinds = parse_backends(names, forms)?;
    let options = SolveOptions {
        tol,
        time_limit: time_limit(time_limit_s),
        ..SolveOptions::default()
    };
    let bar = indicatif::ProgressBar::new(kinds.len() as u64).with_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let progress = |name: &str| {
        bar.set_message(name.to_string());
        bar.inc(1);
    };
    let report = match qp {
        Some(dir) => {
            use signorini::compare::QpCompareError;
            // Each cause as its own error, so that `classify` sees it (a transparent wrapper
            // would hide it): refused files exit 1, a factor that does not fit exits 3.
            signorini::compare::compare_qp(dir, &kinds, &options, progress).map_err(
                |e| match e {
                    QpCompareError::Files(e) => anyhow::Error::new(e),
                    QpCompareError::Preflight(e) => anyhow::Error::new(e),
                    QpCompareError::Run(e) => anyhow::Error::new(e),
                    e @ QpCompareError::NoRows(_) => anyhow::Error::new(e),
                },
            )?
        }
        None => {
            let scene = run::load_scene(common.scene.as_deref())?;
            signorini::compare::compare(&scene, &kinds, &options, &limits(common), progress)?
        }
    };
    bar.finish_and_clear();
    let mut report = report;
    let settings = signorini_core::report::BackendSettings {
        backend: kinds
            .iter()
            .map(|k| k.name().to_string())
            .collect::<Vec<_>>()
            .join(","),
        form: "primal".to_string(),
        tolerance: options.tol,
        time_limit_s: options.time_limit.map(|t| t.as_secs_f64()),
        max_iter: options.max_iter,
        chain: Vec::new(),
    };
    report.provenance = Some(match qp {
        Some(dir) => signorini::contract::qp_provenance(dir, settings)
            .with_context(|| format!("reading {} for its hash", dir.display()))?,
        None => signorini::contract::provenance(common.scene.as_deref(), settings)?,
    });
    let written = signorini::compare::write(out, &report)
        .with_context(|| format!("writing comparison to {}", out.display()))?;
    let mut con = Console::new();
    for line in signorini::compare::table(&report).lines() {
        con.line(line)?;
    }
    for p in &written {
        con.line(format_args!("  wrote {}", p.display()))?;
    }
    con.finish()?;
    let failed: Vec<&str> = report
        .backends
        .iter()
        .filter(|r| r.status != "solved")
        .map(|r| r.backend.as_str())
        .collect();
    if failed.is_empty() {
        Ok(Exit::Success)
    } else {
        warn(format_args!("error: not solved by {}", failed.join(", ")));
        Ok(Exit::NotSolved)
    }
}

/// Every backend compiled in, for `suite`.
const SUITE_BACKENDS: [BackendKind; 6] = [
    BackendKind::Clarabel,
    BackendKind::Osqp,
    BackendKind::DualPgs,
    BackendKind::DualUzawa,
    BackendKind::DualSsn,
    BackendKind::Pdas,
];

fn suite(args: &SuiteArgs) -> Result<Exit> {
    use signorini::suite::{self, bless::Change};
    let backends = if args.backends.is_empty() {
        SUITE_BACKENDS
            .into_iter()
            .filter(|k| k.available())
            .collect()
    } else {
        parse_backends(&args.backends, &[])?
    };
    let settings = suite::SuiteSettings {
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
    };
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
        form: "primal".to_string(),
        tolerance: settings.solve.tol,
        time_limit_s: settings.solve.time_limit.map(|t| t.as_secs_f64()),
        max_iter: settings.solve.max_iter,
        chain: Vec::new(),
    };
    report.provenance = Some(signorini::contract::provenance(None, settings_report)?);
    if let Some(p) = report.provenance.as_mut() {
        // The suite's scenes are many: each case records its own file's hash.
        p.scene_path = Some(args.dir.display().to_string());
        p.scene_sha256 = String::new();
    }
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
    let mut con = Console::new();
    for line in suite::table::table(&report).lines() {
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
        for b in &blessed {
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
                Change::Skipped(why) => {
                    con.line(format_args!("  not blessed {}: {why}", b.case))?
                }
            }
        }
        let unchanged = blessed
            .iter()
            .filter(|b| b.change == Change::Unchanged)
            .count();
        con.line(format_args!(
            "  {unchanged} expectations unchanged (within their tolerances)"
        ))?;
    }
    for p in &written {
        con.line(format_args!("  wrote {}", p.display()))?;
    }
    con.finish()?;
    let errors: Vec<&str> = report
        .cases
        .iter()
        .filter(|c| c.error.is_some())
        .map(|c| c.name.as_str())
        .collect();
    if args.bless {
        if errors.is_empty() {
            return Ok(Exit::Success);
        }
        warn(format_args!(
            "error: could not run, so not blessed: {}",
            errors.join(", ")
        ));
        return Ok(Exit::NotSolved);
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
    Ok(code)
}

fn sweep(args: &SweepArgs) -> Result<Exit> {
    let backends = parse_backends(&args.backends, &[])?;
    let common = &args.common;
    let scene = run::load_scene(common.scene.as_deref())?;
    let plan = signorini::sweep::SweepPlan {
        hmax: args.hmax.clone(),
        bodies: args.bodies.clone(),
        backends,
        tols: args.tol.clone(),
        repeat: args.repeat as usize,
        time_limit: time_limit(args.time_limit),
        resume: args.resume,
        overwrite: args.overwrite,
        shard: args.shard,
        vtu: args.vtu,
    };
    // The timer ticks on its own (it used to freeze while a point ran: the bar was redrawn only
    // when a point ended), and the message names the step under way, not the last one done.
    let bar = indicatif::ProgressBar::new(0).with_style(
        indicatif::ProgressStyle::with_template("{spinner} {bar:30} {pos}/{len} [{elapsed}] {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.enable_steady_tick(Duration::from_millis(250));
    let outcome = signorini::sweep::sweep(
        &scene,
        &plan,
        &SolveOptions::default(),
        &limits(common),
        &args.out,
        |done, total, what| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
            bar.set_message(what.to_string());
        },
    );
    bar.finish_and_clear();
    let outcome = outcome?;
    let title = match args.shard {
        Some(s) => format!("{} (shard {s})", scene.title),
        None => scene.title.clone(),
    };
    let mut written = vec![outcome.csv.clone()];
    written.extend(outcome.plots.iter().cloned());
    written.extend(outcome.files.iter().cloned());
    sweep_report(
        &title,
        &outcome.points,
        &written,
        outcome.failed,
        outcome.skipped,
    )
}

fn sweep_merge(dirs: &[PathBuf], overwrite: bool, out: &std::path::Path) -> Result<Exit> {
    let outcome = signorini::sweep::merge::merge(dirs, out, overwrite)?;
    let mut written = vec![outcome.csv.clone()];
    written.extend(outcome.plots.iter().cloned());
    written.extend(outcome.files.iter().cloned());
    sweep_report(
        &format!(
            "{} (merged from {} shards)",
            outcome.manifest.title,
            dirs.len()
        ),
        &outcome.points,
        &written,
        outcome.failed,
        outcome.skipped,
    )
}

/// The table of a sweep's points, the files written and the summary; exit 2 when a point was
/// not solved or skipped.
fn sweep_report(
    title: &str,
    points: &[signorini::sweep::Point],
    written: &[PathBuf],
    failed: usize,
    skipped: usize,
) -> Result<Exit> {
    let mut con = Console::new();
    con.line(format_args!("{title}: {} points", points.len()))?;
    con.line(format_args!(
        "  {:>8} {:>9} {:<11} {:>8} {:<15} {:>6} {:>10} {:>10} {:>8} {:>9} {:>9}",
        "hmax",
        "dofs",
        "backend",
        "tol",
        "status",
        "iter",
        "solve s",
        "floor s",
        "÷floor",
        "err ref",
        "err fine"
    ))?;
    for p in points {
        con.line(format_args!(
            "  {:>8} {:>9} {:<11} {:>8.0e} {:<15} {:>6} {:>10.4} {:>10.4} {:>8.2} {:>9.1e} {:>9.1e}",
            p.hmax,
            p.dofs,
            p.backend,
            p.tol,
            p.status,
            p.iterations,
            p.solve_s,
            p.floor_s,
            p.ratio_to_floor,
            p.error_vs_reference.unwrap_or(f64::NAN),
            p.error_vs_finest.unwrap_or(f64::NAN)
        ))?;
    }
    for p in written {
        con.line(format_args!("  wrote {}", p.display()))?;
    }
    let summary = format!(
        "sweep: {} of {} points solved, {} not solved, {} skipped after a time limit",
        points.len() - failed,
        points.len() + skipped,
        failed,
        skipped
    );
    if failed + skipped == 0 {
        con.line(summary)?;
        con.finish()?;
        Ok(Exit::Success)
    } else {
        con.finish()?;
        warn(format_args!("error: {summary}"));
        Ok(Exit::NotSolved)
    }
}

/// What `study` was asked to run.
struct StudyArgs<'a> {
    hmax: &'a [f64],
    formulations: &'a [signorini_core::scene::Formulation],
    meshes: &'a [signorini::study::MeshKind],
    elements: &'a [signorini_core::mesh::ElementKind],
    backend: BackendKind,
    tol: f64,
    overwrite: bool,
}

fn study(common: &Common, args: &StudyArgs, out: &std::path::Path) -> Result<Exit> {
    let backend = args.backend;
    anyhow::ensure!(
        backend.available(),
        "backend \"{backend}\" is not compiled in; rebuild with `--features osqp`"
    );
    let scene = run::load_scene(common.scene.as_deref())?;
    let plan = signorini::study::StudyPlan {
        hmax: args.hmax.to_vec(),
        formulations: args.formulations.to_vec(),
        meshes: args.meshes.to_vec(),
        elements: args.elements.to_vec(),
        backend,
        overwrite: args.overwrite,
    };
    let options = SolveOptions {
        tol: args.tol,
        ..SolveOptions::default()
    };
    let bar = indicatif::ProgressBar::new(0).with_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} [{elapsed}] {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let outcome = signorini::study::study(
        &scene,
        &plan,
        &options,
        &limits(common),
        out,
        |done, total, what| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
            bar.set_message(what.to_string());
        },
    )?;
    bar.finish_and_clear();
    let mut con = Console::new();
    con.line(format_args!(
        "{}: {} points",
        scene.title,
        outcome.points.len()
    ))?;
    for s in &outcome.skipped {
        con.line(format_args!(
            "  skipped {}: does not apply ({})",
            s.combination, s.reason
        ))?;
    }
    con.line(format_args!(
        "  {:<32} {:>8} {:>9} {:<11} {:>9} {:>10} {:>10} {:>10} {:>10}",
        "combination", "hmax", "dofs", "status", "total s", "err a", "err p0", "err pmax", "patch"
    ))?;
    let e = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:+.2e}"));
    for p in &outcome.points {
        con.line(format_args!(
            "  {:<32} {:>8} {:>9} {:<11} {:>9.4} {:>10} {:>10} {:>10} {:>10}",
            p.combination(),
            p.hmax,
            p.dofs,
            p.status,
            p.total_s,
            e(p.error_half_width),
            e(p.error_peak_pressure),
            e(p.error_peak_nodal_pressure),
            e(p.pressure_deviation)
        ))?;
    }
    con.line("  convergence rates (|error| ~ h^rate, solved points):")?;
    for r in &outcome.rates {
        con.line(format_args!(
            "    {:<32} {:<36} {}",
            r.combination,
            r.measure,
            r.rate
                .map_or("-".to_string(), |v| format!("{v:.2} ({} meshes)", r.points))
        ))?;
    }
    con.line(format_args!("  wrote {}", outcome.csv.display()))?;
    if let Some(p) = &outcome.plot {
        con.line(format_args!("  wrote {}", p.display()))?;
    }
    con.finish()?;
    if outcome.failed == 0 {
        Ok(Exit::Success)
    } else {
        for p in outcome.points.iter().filter(|p| !p.solved()) {
            warn(format_args!(
                "not solved: {} hmax {}: {} {}",
                p.combination(),
                p.hmax,
                p.status,
                p.message
            ));
        }
        warn(format_args!(
            "error: study: {} of {} points not solved",
            outcome.failed,
            outcome.points.len()
        ));
        Ok(Exit::NotSolved)
    }
}

/// The backends `compare` and `sweep` run when `--backends` is not given (osqp only when built
/// with it).
const DEFAULT_BACKENDS: [BackendKind; 4] = [
    BackendKind::Clarabel,
    BackendKind::Osqp,
    BackendKind::DualPgs,
    BackendKind::DualUzawa,
];

/// The backends named (or the defaults), each of clarabel and osqp once per form of `forms`
/// when it is not empty (the other backends once, in their own form).
fn parse_backends(names: &[BackendKind], forms: &[Form]) -> Result<Vec<BackendKind>> {
    let named: Vec<BackendKind> = if names.is_empty() {
        DEFAULT_BACKENDS
            .into_iter()
            .filter(|k| k.available())
            .collect()
    } else {
        names.to_vec()
    };
    let mut kinds: Vec<BackendKind> = Vec::with_capacity(named.len() * 2);
    for kind in named {
        if forms.is_empty() || !kind.has_forms() {
            kinds.push(kind);
        } else {
            for &form in forms {
                kinds.push(kind.with_form(form)?);
            }
        }
    }
    let mut seen = std::collections::HashSet::new();
    kinds.retain(|k| seen.insert(*k));
    anyhow::ensure!(!kinds.is_empty(), "--backends names no backend");
    for k in &kinds {
        anyhow::ensure!(
            k.available(),
            "backend \"{k}\" is not compiled in; rebuild with `--features osqp`"
        );
    }
    Ok(kinds)
}

fn export(common: &Common, out: &std::path::Path) -> Result<Exit> {
    let scene = run::load_scene(common.scene.as_deref())?;
    let prepared = run::prepare(&scene, &limits(common))?;
    let qp = &prepared.qp;
    let written = signorini::export::export(out, &scene, &prepared.model, qp)
        .with_context(|| format!("exporting to {}", out.display()))?;
    let mut con = Console::new();
    con.line(format_args!(
        "{}: {} unknowns, {} contact rows",
        scene.title,
        qp.dofs(),
        qp.rows()
    ))?;
    for p in &written {
        con.line(format_args!("  wrote {}", p.display()))?;
    }
    con.finish()?;
    Ok(Exit::Success)
}

fn check(common: &Common) -> Result<Exit> {
    let scene = run::load_scene(common.scene.as_deref())?;
    // Everything solve verifies before its backend runs; "valid" only once all of it passed.
    let report = signorini::check::check(&scene, &limits(common))?;
    let mut con = Console::new();
    con.line(format_args!("{}: valid", scene.title))?;
    let e = &report.estimate;
    for (body, estimate) in scene.bodies.iter().zip(&e.bodies) {
        con.line(format_args!(
            "  body {:<10} hmax {:<8} ~{} elements (estimated before meshing)",
            body.name, body.hmax, estimate.elements
        ))?;
    }
    con.line(format_args!(
        "  {} elements meshed (~{} estimated), {} free DOFs, {} contact rows",
        report.elements, e.elements, report.dofs, report.constraints
    ))?;
    con.line(format_args!(
        "  memory estimate for solve: {:.2} GiB (clarabel, osqp), {:.2} GiB (dual backends)",
        e.bytes as f64 / 1024f64.powi(3),
        e.bytes_dual as f64 / 1024f64.powi(3)
    ))?;
    con.line(format_args!(
        "  {} dirichlet, {} neumann, {} contact pair(s), {} probe(s)",
        scene.dirichlet.len(),
        scene.neumann.len(),
        scene.contacts.len(),
        scene.probes.len()
    ))?;
    con.finish()?;
    Ok(Exit::Success)
}

fn schema(document: signorini::contract::Document) -> Result<Exit> {
    let text = serde_json::to_string_pretty(&signorini::contract::schema(document))
        .context("serialising the schema")?;
    let mut con = Console::new();
    con.line(text)?;
    con.finish()?;
    Ok(Exit::Success)
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // --help and --version are not errors; everything else is a usage error (1).
            let _ = e.print();
            return if e.use_stderr() {
                Exit::Input.into()
            } else {
                Exit::Success.into()
            };
        }
    };
    let result = match &cli.command {
        Command::Solve {
            common,
            backend,
            form,
            chain,
            tol,
            time_limit,
            out,
            vtu,
        } => solve(
            common,
            &SolveArgs {
                backend: *backend,
                form: *form,
                chain,
                tol: *tol,
                time_limit_s: *time_limit,
                vtu: *vtu,
            },
            out,
        ),
        Command::Compare {
            common,
            backends,
            forms,
            tol,
            time_limit,
            out,
            qp,
        } => compare(
            common,
            backends,
            forms,
            *tol,
            *time_limit,
            out,
            qp.as_deref(),
        ),
        Command::Export { common, out } => export(common, out),
        Command::Sweep { args, action } => match action {
            Some(SweepAction::Merge {
                dirs,
                overwrite,
                out,
            }) => sweep_merge(dirs, *overwrite, out),
            None => sweep(args),
        },
        Command::Study {
            common,
            hmax,
            formulations,
            meshes,
            elements,
            backend,
            tol,
            overwrite,
            out,
        } => study(
            common,
            &StudyArgs {
                hmax,
                formulations,
                meshes,
                elements,
                backend: *backend,
                tol: *tol,
                overwrite: *overwrite,
            },
            out,
        ),
        Command::Suite(args) => suite(args),
        Command::Check { common } => check(common),
        Command::Schema { document } => schema(*document),
    };
    match result {
        Ok(code) => code.into(),
        Err(e) => {
            warn(format_args!("error: {e:#}"));
            classify(&e).into()
        }
    }
}
