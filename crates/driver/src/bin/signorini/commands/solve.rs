//! `signorini solve`: one scene, one backend (or auto's chain), result.json and the files beside it.

use anyhow::{Context, Result};
use signorini::auto::AutoBackend;
use std::path::PathBuf;

use signorini::backends::{make_backend, BackendKind, ChoiceParser, Form};
use signorini::exit::Exit;
use signorini::run;
use signorini_core::qp::{QpStatus, SolveOptions};

use crate::args::{limits, parse_backends, Common, SolveFlags};
use crate::console::{warn, Console};

/// `signorini solve SCENE …`: the options of a solve.
#[derive(clap::Args)]
pub(crate) struct SolveArgs {
    #[command(flatten)]
    pub(crate) common: Common,
    /// QP backend: auto is the fastest likely to succeed, falling back to a robust one (see
    /// docs/scene.md); clarabel/dual and osqp/dual are the condensed dual form.
    #[arg(long, default_value = "auto", value_parser = ChoiceParser::<BackendKind>::new())]
    pub(crate) backend: BackendKind,
    /// Formulation for clarabel and osqp: primal (sparse, in the displacements) or dual
    /// (condensed, dense in the contact forces; not for bodies held by contact alone).
    /// `--backend clarabel --form dual` is `--backend clarabel/dual`.
    #[arg(long, value_parser = ChoiceParser::<Form>::new())]
    pub(crate) form: Option<Form>,
    /// With `--backend auto`: the backends to try, in order, instead of auto's rule
    /// (e.g. dual-ssn,clarabel).
    #[arg(long, value_delimiter = ',', value_parser = ChoiceParser::<BackendKind>::new())]
    pub(crate) chain: Vec<BackendKind>,
    #[command(flatten)]
    pub(crate) solve: SolveFlags,
    /// Output directory (created if missing).
    #[arg(long, default_value = "out")]
    pub(crate) out: PathBuf,
    /// Encoding of solution.vtu: binary (zlib-compressed, base64 appended data; small and
    /// fast to read) or ascii (decimal text, several times larger).
    #[arg(long, value_enum, default_value_t = signorini::output::VtuFormat::Binary)]
    pub(crate) vtu: signorini::output::VtuFormat,
}

pub(crate) fn solve(args: &SolveArgs) -> Result<Exit> {
    let (common, out) = (&args.common, args.out.as_path());
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
    let options = args.solve.options();
    let settings = signorini_core::report::BackendSettings {
        backend: kind.name().to_string(),
        form: signorini::contract::forms(&[kind]),
        tolerance: options.tol,
        time_limit_s: options.time_limit.map(|t| t.as_secs_f64()),
        max_iter: options.max_iter,
        chain: args.chain.iter().map(|k| k.name().to_string()).collect(),
        coulomb: options.coulomb,
    };
    let provenance = signorini::contract::provenance(common.scene.as_deref(), settings)?;
    let mut outcome = if kind == BackendKind::Auto {
        solve_auto(args, &scene, &options)?
    } else {
        let mut backend = make_backend(kind)?;
        run::solve_scene(&scene, backend.as_mut(), &options, &limits(common))?
    };
    outcome.report.provenance = Some(provenance);
    let written = run::write_outputs_with(out, &scene, &outcome, args.vtu)
        .with_context(|| format!("writing results to {}", out.display()))?;
    print_report(&outcome.report, &written)?;
    Ok(verdict(&outcome))
}

/// Solves with `auto` (its rule, or the chain of `--chain`), printing each attempt and its
/// choice, and records the choice in the report.
fn solve_auto(
    args: &SolveArgs,
    scene: &signorini_core::scene::Scene,
    options: &SolveOptions,
) -> Result<run::Outcome> {
    let common = &args.common;
    let mut auto = if args.chain.is_empty() {
        AutoBackend::default()
    } else {
        let kinds = parse_backends(&args.chain, &[])?;
        anyhow::ensure!(
            !kinds.contains(&BackendKind::Auto),
            "--chain cannot hold auto itself"
        );
        AutoBackend::with_kinds(kinds, "the chain given by --chain")
    };
    let priced = if args.chain.is_empty() {
        run::Priced::Kind(BackendKind::Auto)
    } else {
        run::Priced::Chain(parse_backends(&args.chain, &[])?)
    };
    let result = run::solve_scene_priced(scene, &mut auto, priced, options, &limits(common));
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
    Ok(outcome)
}

/// Prints the run's summary: DOFs and status, each body, each contact pair with rows, the
/// residuals, the times and the files written.
fn print_report(
    r: &signorini_core::report::RunReport,
    written: &[std::path::PathBuf],
) -> Result<()> {
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
    for p in written {
        con.line(format_args!("  wrote {}", p.display()))?;
    }
    con.finish()?;
    Ok(())
}

/// The exit code of a solve, after its warnings: 0 when solved, else 2 with the status.
fn verdict(outcome: &run::Outcome) -> Exit {
    let r = &outcome.report;
    for w in &r.warnings {
        warn(format_args!("warning: {}", w.message));
    }
    if outcome.solution.status == QpStatus::Solved {
        Exit::Success
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
        Exit::NotSolved
    }
}
