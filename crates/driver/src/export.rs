//! `signorini export`: the reduced QP of a scene as Matrix Market files plus the DOF and row
//! maps, so that any outside QP solver can be run on exactly our problem.
//!
//! Files: `A.mtx` (stiffness, coordinate real general, both triangles), `f.mtx` (load, array),
//! `B.mtx` (contact rows, coordinate), `g.mtx` (gaps, array), `dofs.csv` (unknown → body, node,
//! component, coordinates), `rows.csv` (row → pair, slave body and node, position, gap) and
//! `README.txt` stating the problem `min ½xᵀAx − fᵀx s.t. Bx ≤ g`; when A is singular (a body
//! held by contact alone), also `N.mtx`, a basis of A's null space (the floating bodies'
//! rigid-body modes, array n×k), which the dual backends need.  Values are the user's units (not
//! the internal nondimensional ones).

use std::io::Write;
use std::path::{Path, PathBuf};

use signorini_core::model::Model;
use signorini_core::qp::QpProblem;
use signorini_core::scene::Scene;

use crate::outdir::{DirLock, OutputSet};
use crate::output::OutputError;

/// A vector as a Matrix Market array n×1.
fn write_dense(w: &mut dyn Write, v: &[f64]) -> std::io::Result<()> {
    writeln!(w, "%%MatrixMarket matrix array real general")?;
    writeln!(w, "% written by signorini")?;
    writeln!(w, "{} 1", v.len())?;
    for x in v {
        // `{:e}` of an f64 is the shortest text that reads back to the same value.
        writeln!(w, "{x:e}")?;
    }
    Ok(())
}

/// The exported files; `README.txt` (moved into place last) marks a complete set; `N.mtx` only
/// when A is singular (an earlier export's is removed otherwise).
pub const EXPORT_FILES: [&str; 8] = [
    "A.mtx",
    "f.mtx",
    "B.mtx",
    "g.mtx",
    "N.mtx",
    "dofs.csv",
    "rows.csv",
    "README.txt",
];

/// A basis of k vectors of length n as a Matrix Market array n×k (column-major).
fn write_columns(w: &mut dyn Write, columns: &[Vec<f64>]) -> std::io::Result<()> {
    let n = columns.first().map_or(0, Vec::len);
    writeln!(w, "%%MatrixMarket matrix array real general")?;
    writeln!(
        w,
        "% written by signorini: a basis of the null space of A, one column per mode"
    )?;
    writeln!(w, "{n} {}", columns.len())?;
    for c in columns {
        for x in c {
            writeln!(w, "{x:e}")?;
        }
    }
    Ok(())
}

/// Writes the exported files into `dir` (created if missing) as one output set (see
/// [`crate::outdir`]): under the directory's lock, staged and moved into place together, so a
/// failed export leaves the previous files unchanged.
pub fn export(
    dir: &Path,
    scene: &Scene,
    model: &Model,
    qp: &QpProblem,
) -> Result<Vec<PathBuf>, OutputError> {
    let lock = DirLock::acquire(dir)?;
    let mut set = OutputSet::new(&lock, Some("README.txt"), &EXPORT_FILES)?;
    let mut put = |name: &str, f: &mut dyn FnMut(&mut dyn Write) -> std::io::Result<()>| {
        set.write(name, |w| f(w)).map(|_| ())
    };
    put("A.mtx", &mut |w| {
        sprs::io::write_matrix_market_to_bufwrite(w, &qp.stiffness)
    })?;
    put("f.mtx", &mut |w| write_dense(w, &qp.load))?;
    put("B.mtx", &mut |w| {
        sprs::io::write_matrix_market_to_bufwrite(w, &qp.constraints)
    })?;
    put("g.mtx", &mut |w| write_dense(w, &qp.gap))?;
    if !qp.kernel.is_empty() {
        put("N.mtx", &mut |w| write_columns(w, &qp.kernel))?;
    }
    put("dofs.csv", &mut |w| write_dofs(w, scene, model))?;
    put("rows.csv", &mut |w| write_rows(w, scene, model, qp))?;
    put("README.txt", &mut |w| write_readme(w, scene, qp))?;
    set.commit()
}

/// `dofs.csv`: each unknown's body, node, component and coordinates.
fn write_dofs(w: &mut dyn Write, scene: &Scene, model: &Model) -> std::io::Result<()> {
    let mut csv = csv::Writer::from_writer(w);
    csv.write_record(["unknown", "body", "node", "component", "x", "y"])?;
    for (k, &d) in model.free.iter().enumerate() {
        let node = d / 2;
        let body = (0..model.meshes.len())
            .rev()
            .find(|&b| model.dofs.node_offset(b) <= node)
            .unwrap_or(0);
        let local = node - model.dofs.node_offset(body);
        let p = model.meshes[body].nodes[local];
        csv.write_record([
            k.to_string(),
            scene.bodies[body].name.clone(),
            local.to_string(),
            ["x", "y"][d % 2].to_string(),
            format!("{:e}", p[0]),
            format!("{:e}", p[1]),
        ])?;
    }
    csv.flush()
}

/// `rows.csv`: each contact row's pair, slave body and node, position, masters, normal and gap.
fn write_rows(
    w: &mut dyn Write,
    scene: &Scene,
    model: &Model,
    qp: &QpProblem,
) -> std::io::Result<()> {
    let mut csv = csv::Writer::from_writer(w);
    csv.write_record([
        "row",
        "pair",
        "slave",
        "slave_node",
        "x",
        "y",
        "masters",
        "nx",
        "ny",
        "gap",
    ])?;
    let mut row = 0;
    for pair in &model.contacts {
        for r in &pair.rows {
            csv.write_record([
                row.to_string(),
                (pair.pair + 1).to_string(),
                scene.bodies[pair.slave].name.clone(),
                r.slave_node.to_string(),
                format!("{:e}", r.position[0]),
                format!("{:e}", r.position[1]),
                r.masters
                    .iter()
                    .map(|(k, w)| format!("{k}:{w:e}"))
                    .collect::<Vec<_>>()
                    .join(";"),
                format!("{:e}", r.normal[0]),
                format!("{:e}", r.normal[1]),
                format!("{:e}", qp.gap[row]),
            ])?;
            row += 1;
        }
    }
    csv.flush()
}

/// `README.txt`: the problem the files state, its sizes, and the null space when A is singular.
fn write_readme(w: &mut dyn Write, scene: &Scene, qp: &QpProblem) -> std::io::Result<()> {
    writeln!(w, "Scene: {}", scene.title)?;
    writeln!(w, "Problem: minimise 1/2 x'Ax - f'x subject to Bx <= g")?;
    writeln!(
        w,
        "n = {} unknowns (free DOFs, see dofs.csv), m = {} contact rows (see rows.csv).",
        qp.dofs(),
        qp.rows()
    )?;
    writeln!(
        w,
        "A is symmetric (both triangles stored); the multipliers of Bx <= g are the contact forces."
    )?;
    if !qp.kernel.is_empty() {
        writeln!(
            w,
            "A is singular: {} rigid-body mode(s) of floating bodies are held only by contact; N.mtx holds a basis of A's null space (n x {}).",
            qp.kernel.len(),
            qp.kernel.len()
        )?;
    }
    Ok(())
}
