//! `signorini`: frictionless contact of elastic bodies in 2D, solved by several QP backends.
//!
//! Exit codes (see `docs/scene.md`): 0 solved or valid, 1 bad input or usage, 2 not solved,
//! 3 I/O or resource error.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use signorini::backends::{BackendKind, ChoiceParser, Form, NamedParser};
use signorini::exit::{classify, Exit};

mod args;
mod commands;
mod console;

use args::{parse_factor, parse_shard, parse_time_limit, parse_tol, Common};
use commands::{
    check::check,
    compare::compare,
    export::export,
    schema::schema,
    solve::{solve, SolveArgs},
    study::{study, StudyArgs},
    suite::suite,
    sweep::{sweep, sweep_merge},
};
use console::warn;

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
    /// Run only the cases whose name contains one of these texts (comma-separated), e.g.
    /// `--only strip,contrast`.
    #[arg(long, value_delimiter = ',')]
    only: Vec<String>,
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
    // A memory limit the user set but mistyped is refused before anything runs, naming it.
    if let Err(e) = signorini_core::memory::limit_from_env() {
        warn(format_args!("error: {e}"));
        return Exit::Input.into();
    }
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
