//! `signorini check`: a scene validated as solve would, without solving.

use anyhow::Result;
use signorini::exit::Exit;
use signorini::run;

use crate::args::{limits, Common};
use crate::console::Console;

pub(crate) fn check(common: &Common) -> Result<Exit> {
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
