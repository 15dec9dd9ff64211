//! `signorini study`: discretisation error against time for a scene with a reference.

use anyhow::Result;
use std::path::PathBuf;

use signorini::backends::{BackendKind, ChoiceParser, NamedParser};
use signorini::exit::Exit;
use signorini::run;
use signorini::study::StudyOutcome;
use signorini_core::qp::SolveOptions;

use crate::args::{limits, parse_tol, Common};
use crate::console::{warn, Console};

/// `signorini study SCENE …`: the options of a study.
#[derive(clap::Args)]
pub(crate) struct StudyArgs {
    #[command(flatten)]
    pub(crate) common: Common,
    /// Comma-separated sizes of the coarsest body, e.g. 0.04,0.02,0.01; every other size of
    /// the scene (other bodies, [[body.refine]]) is scaled by the same factor.
    #[arg(long, value_delimiter = ',', required = true)]
    pub(crate) hmax: Vec<f64>,
    /// Comma-separated contact formulations set on every pair.
    #[arg(long, value_delimiter = ',', default_value = "node-to-segment,mortar", value_parser = NamedParser::new(&["node-to-segment", "mortar"], signorini::study::parse_formulation))]
    pub(crate) formulations: Vec<signorini_core::scene::Formulation>,
    /// Comma-separated mesh kinds: uniform (every [[body.refine]] dropped), graded (kept).
    #[arg(long, value_delimiter = ',', default_value = "uniform,graded", value_parser = NamedParser::new(&["uniform", "graded"], |s| s.parse::<signorini::study::MeshKind>()))]
    pub(crate) meshes: Vec<signorini::study::MeshKind>,
    /// Comma-separated elements set on the bodies that are axis-aligned rectangles.
    #[arg(long, value_delimiter = ',', default_value = "p1,q1", value_parser = NamedParser::new(&["p1", "q1"], signorini::study::parse_element))]
    pub(crate) elements: Vec<signorini_core::mesh::ElementKind>,
    /// QP backend every point is solved with (as for solve).
    #[arg(long, default_value = "auto", value_parser = ChoiceParser::<BackendKind>::new())]
    pub(crate) backend: BackendKind,
    /// Relative KKT tolerance every point must meet to count as solved.
    #[arg(long, default_value_t = 1e-9, value_parser = parse_tol)]
    pub(crate) tol: f64,
    /// Replace an existing DIR/study.csv (without it, an existing file is refused).
    #[arg(long)]
    pub(crate) overwrite: bool,
    /// Output directory for study.csv and accuracy.svg (created if missing).
    #[arg(long, default_value = "out")]
    pub(crate) out: PathBuf,
}

pub(crate) fn study(args: &StudyArgs) -> Result<Exit> {
    let (common, out) = (&args.common, args.out.as_path());
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
    print_outcome(&scene.title, &outcome)?;
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

/// Prints the study's points, skipped combinations, convergence rates and files written.
fn print_outcome(title: &str, outcome: &StudyOutcome) -> Result<()> {
    let mut con = Console::new();
    con.line(format_args!("{}: {} points", title, outcome.points.len()))?;
    for s in &outcome.skipped {
        con.line(format_args!(
            "  skipped {}: does not apply ({})",
            s.combination, s.reason
        ))?;
    }
    // Cattaneo's columns only when some point has them: frictionless studies print as before.
    let cattaneo = outcome
        .points
        .iter()
        .any(|p| p.error_stick_half_width.is_some() || p.error_tangential_traction.is_some());
    let mut head = format!(
        "  {:<32} {:>8} {:>9} {:<11} {:>9} {:>10} {:>10} {:>10} {:>10}",
        "combination", "hmax", "dofs", "status", "total s", "err a", "err p0", "err pmax", "patch"
    );
    if cattaneo {
        head.push_str(&format!(" {:>10} {:>10}", "err c", "err q"));
    }
    con.line(head)?;
    let e = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:+.2e}"));
    for p in &outcome.points {
        let mut row = format!(
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
        );
        if cattaneo {
            row.push_str(&format!(
                " {:>10} {:>10}",
                e(p.error_stick_half_width),
                e(p.error_tangential_traction)
            ));
        }
        con.line(row)?;
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
    Ok(())
}
