//! `signorini`: contact of elastic bodies in 2D — frictionless, Tresca or Coulomb friction —
//! solved by several QP backends.
//!
//! Exit codes (see `docs/scene.md`): 0 solved or valid, 1 bad input or usage, 2 not solved,
//! 3 I/O or resource error.

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use signorini::exit::{classify, Exit};

mod args;
mod commands;
mod console;

use commands::{
    check::{check, CheckArgs},
    compare::{compare, CompareArgs},
    export::{export, ExportArgs},
    qpset::{qpset, QpsetArgs},
    schema::{schema, SchemaArgs},
    solve::{solve, SolveArgs},
    study::{study, StudyArgs},
    suite::{suite, SuiteArgs},
    sweep::{sweep, sweep_merge, SweepAction, SweepArgs},
};
use console::warn;

#[derive(Parser)]
#[command(
    name = "signorini",
    version,
    about = "2D contact of elastic bodies by FEM (frictionless, Tresca or Coulomb friction), through several QP backends",
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
    Solve(SolveArgs),
    /// Mesh and assemble once, then solve the same QP with several backends and compare them.
    Compare(CompareArgs),
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
    Study(StudyArgs),
    /// Run every scene of a directory (recursively) through every backend and check each answer
    /// against the scene's stored expectation NAME.expected.json; write suite.json, suite.csv,
    /// suite.xml (JUnit) and suite.svg (performance profile).  Exit 2 when a case regressed.
    Suite(SuiteArgs),
    /// Write the scene's QP (A, f, B, g as Matrix Market; blocks.csv: friction's box rows and
    /// their bounds) and its DOF and row maps.
    Export(ExportArgs),
    /// Export every scene under the given directories as a qpbenchmark test set (one .npz per
    /// problem, the Python module, references from our `auto` backend); see
    /// docs/qp-benchmark.md.
    Qpset(QpsetArgs),
    /// Validate a scene exactly as solve does (parse, estimate, mesh, assemble), without solving.
    Check(CheckArgs),
    /// Print the JSON Schema (draft 2020-12) of the scene file, result.json, a suite's
    /// NAME.expected.json or suite.json, generated from the program's own types (see
    /// docs/scene.md).
    Schema(SchemaArgs),
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
        Command::Solve(args) => solve(args),
        Command::Compare(args) => compare(args),
        Command::Export(args) => export(args),
        Command::Qpset(args) => qpset(args),
        Command::Sweep { args, action } => match action {
            Some(SweepAction::Merge {
                dirs,
                overwrite,
                out,
            }) => sweep_merge(dirs, *overwrite, out),
            None => sweep(args),
        },
        Command::Study(args) => study(args),
        Command::Suite(args) => suite(args),
        Command::Check(args) => check(args),
        Command::Schema(args) => schema(args),
    };
    match result {
        Ok(code) => code.into(),
        Err(e) => {
            warn(format_args!("error: {e:#}"));
            classify(&e).into()
        }
    }
}
