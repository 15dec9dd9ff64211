//! `signorini export`: the reduced QP of a scene as Matrix Market files plus the DOF and row
//! maps, so that any outside QP solver can be run on exactly our problem.
//!
//! Files: `A.mtx` (stiffness, coordinate real general, both triangles), `f.mtx` (load, array),
//! `B.mtx` (constraint rows, coordinate), `g.mtx` (gaps, array), `blocks.csv` (each row's kind,
//! `non-negative` or `box`, and a box row's bound: see [`crate::qp_files`]), `dofs.csv` (unknown
//! → body, node, component, coordinates), `rows.csv` (row → pair, slave body and node,
//! position, gap; with friction also each row's kind and a tangential row's normal row and
//! friction law) and `README.txt` stating the problem
//!
//! ```text
//! min ½xᵀAx − fᵀx + Σ_{box rows i} sᵢ |(Bx − g)ᵢ|   s.t.  (Bx)ᵢ ≤ gᵢ on the non-negative rows
//! ```
//!
//! (without friction every row is non-negative: `min ½xᵀAx − fᵀx s.t. Bx ≤ g`); when A is
//! singular (a body held by contact alone), also `N.mtx`, a basis of A's null space (the floating
//! bodies' rigid-body modes, array n×k), which the dual backends need.  Values are the user's
//! units (not the internal nondimensional ones).
//!
//! Tresca rows carry their fixed bound.  Coulomb friction is not a QP (the bound μ max(0, λₙ)
//! depends on the answer): its rows are written with the bounds of a solved answer
//! ([`coulomb_snapshot`], [`BoxBounds::CoulombSnapshot`]) — the last Tresca problem of the fixed
//! point, whose solution is that answer — and README.txt says so.

use std::io::Write;
use std::path::{Path, PathBuf};

use signorini_core::model::Model;
use signorini_core::qp::{row_sets, ConstraintBlock, QpError, QpProblem, RowSet};
use signorini_core::scene::{Friction, Scene};

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
pub const EXPORT_FILES: [&str; 9] = [
    "A.mtx",
    "f.mtx",
    "B.mtx",
    "g.mtx",
    "N.mtx",
    "blocks.csv",
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

/// Where the bounds of an export's box rows come from.
#[derive(Debug, Clone, PartialEq)]
pub enum BoxBounds {
    /// The scene's own: Tresca's fixed bounds (or no box row at all).
    Scene,
    /// The scene has Coulomb rows, bounded by μ max(0, λₙ) of a solved answer (Tresca rows keep
    /// their fixed bound): a Tresca snapshot of the Coulomb problem ([`coulomb_snapshot`]).
    CoulombSnapshot {
        /// The backend that solved the scene.
        backend: String,
        /// The tolerance its answer met.
        tolerance: f64,
        /// Its objective (with the box term at these bounds), the user's units.
        objective: f64,
    },
}

/// Whether `model` has a Coulomb row (its export then needs the bounds of an answer).
pub fn has_coulomb(model: &Model) -> bool {
    model
        .tangential
        .iter()
        .any(|t| matches!(t.law, Friction::Coulomb(_)))
}

/// `qp` (the model's QP) with every tangential row bounded by its law at the answer's
/// multipliers `multipliers` (one per row of B, the user's units): μ max(0, λₙ) for a Coulomb
/// row (λₙ its normal row's multiplier), Tresca's fixed bound for a Tresca row.  At the bounds of
/// a Coulomb answer that answer satisfies the Tresca problem's conditions exactly as Coulomb's:
/// the last problem of the fixed point (`signorini_core::solve`).
pub fn coulomb_snapshot(
    model: &Model,
    qp: &QpProblem,
    multipliers: &[f64],
) -> Result<QpProblem, QpError> {
    if multipliers.len() != qp.rows() || model.tangential.len() > qp.rows() {
        return Err(QpError::Dimensions(format!(
            "{} multipliers and {} tangential rows for a QP of {} rows",
            multipliers.len(),
            model.tangential.len(),
            qp.rows()
        )));
    }
    let normal = qp.rows() - model.tangential.len();
    let mut blocks = vec![ConstraintBlock::NonNegative { rows: normal }];
    if !model.tangential.is_empty() {
        blocks.push(ConstraintBlock::Box {
            bounds: model
                .tangential
                .iter()
                .map(|t| t.bound(multipliers[t.normal_row]))
                .collect(),
        });
    }
    qp.clone().with_blocks(blocks)
}

/// Writes the exported files into `dir` (created if missing) as one output set (see
/// [`crate::outdir`]): under the directory's lock, staged and moved into place together, so a
/// failed export leaves the previous files unchanged.  `qp` is the problem written (a Coulomb
/// scene's with the bounds of [`coulomb_snapshot`]), `bounds` says where its box bounds come
/// from (README.txt states it).
pub fn export(
    dir: &Path,
    scene: &Scene,
    model: &Model,
    qp: &QpProblem,
    bounds: &BoxBounds,
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
    put("blocks.csv", &mut |w| write_blocks(w, qp))?;
    put("dofs.csv", &mut |w| write_dofs(w, scene, model))?;
    put("rows.csv", &mut |w| write_rows(w, scene, model, qp))?;
    put("README.txt", &mut |w| {
        write_readme(w, scene, model, qp, bounds)
    })?;
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

/// `blocks.csv`: each row's kind and, for a box row, its bound (the layout
/// [`crate::qp_files::read_blocks`] reads).
fn write_blocks(w: &mut dyn Write, qp: &QpProblem) -> std::io::Result<()> {
    writeln!(w, "{}", crate::qp_files::BLOCKS_HEADER)?;
    for (row, set) in row_sets(&qp.blocks).enumerate() {
        match set {
            RowSet::NonNegative => writeln!(w, "{row},non-negative,")?,
            RowSet::Box(s) => writeln!(w, "{row},box,{s:e}")?,
        }
    }
    Ok(())
}

/// `rows.csv`: each row's pair, slave body and node, position, masters, normal and gap; with
/// friction also its kind (`normal` or `tangential`) and, for a tangential row, its normal row
/// and its friction law and coefficient (`tresca` with the traction, `coulomb` with μ).  A
/// frictionless scene's file has the first ten columns only (as before tangential rows existed).  A tangential row shares
/// its normal row's node, masters and normal n; it measures the slip along t = (ny, −nx).
fn write_rows(
    w: &mut dyn Write,
    scene: &Scene,
    model: &Model,
    qp: &QpProblem,
) -> std::io::Result<()> {
    let mut csv = csv::Writer::from_writer(w);
    let mut header = vec![
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
    ];
    // Without friction the file stays as it was before tangential rows were exported.
    let friction = !model.tangential.is_empty();
    if friction {
        header.extend(["kind", "normal_row", "law", "coefficient"]);
    }
    csv.write_record(&header)?;
    // The normal rows in B's order (pair by pair); the tangential rows follow, each naming one.
    let normal: Vec<_> = model
        .contacts
        .iter()
        .flat_map(|pair| pair.rows.iter().map(move |r| (pair, r)))
        .collect();
    if normal.len() + model.tangential.len() != qp.rows()
        || model
            .tangential
            .iter()
            .any(|t| t.normal_row >= normal.len())
    {
        // A bug, reported rather than written as a wrong map.
        return Err(std::io::Error::other(format!(
            "the model has {} normal and {} tangential rows but the QP {}",
            normal.len(),
            model.tangential.len(),
            qp.rows()
        )));
    }
    let place = |row: usize, normal_row: usize| -> Vec<String> {
        let (pair, r) = normal[normal_row];
        vec![
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
        ]
    };
    for k in 0..normal.len() {
        let mut record = place(k, k);
        if friction {
            record.extend(["normal", "", "", ""].map(String::from));
        }
        csv.write_record(&record)?;
    }
    for (slot, t) in model.tangential.iter().enumerate() {
        let (law, coefficient) = match t.law {
            Friction::Tresca(s) => ("tresca", s),
            Friction::Coulomb(mu) => ("coulomb", mu),
        };
        let mut record = place(normal.len() + slot, t.normal_row);
        record.extend([
            "tangential".to_string(),
            t.normal_row.to_string(),
            law.to_string(),
            format!("{coefficient:e}"),
        ]);
        csv.write_record(&record)?;
    }
    csv.flush()
}

/// `README.txt`: the problem the files state (with the box term when there are box rows), its
/// sizes, where a Coulomb scene's bounds come from, and the null space when A is singular.
fn write_readme(
    w: &mut dyn Write,
    scene: &Scene,
    model: &Model,
    qp: &QpProblem,
    bounds: &BoxBounds,
) -> std::io::Result<()> {
    let boxes = row_sets(&qp.blocks)
        .filter(|s| matches!(s, RowSet::Box(_)))
        .count();
    writeln!(w, "Scene: {}", scene.title)?;
    if boxes == 0 {
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
    } else {
        writeln!(
            w,
            "Problem: minimise 1/2 x'Ax - f'x + sum over the box rows i of s_i |(Bx - g)_i|"
        )?;
        writeln!(
            w,
            "         subject to (Bx)_i <= g_i on the non-negative rows"
        )?;
        writeln!(
            w,
            "n = {} unknowns (free DOFs, see dofs.csv), m = {} rows (see rows.csv): {} non-negative (normal contact rows), {} box (tangential friction rows).",
            qp.dofs(),
            qp.rows(),
            qp.rows() - boxes,
            boxes
        )?;
        writeln!(
            w,
            "blocks.csv names each row's kind and a box row's bound s_i >= 0: the multiplier of a non-negative row is >= 0 (the normal contact force), that of a box row lies in [-s_i, s_i] (the tangential friction force; s_i |r_i| = lambda_i r_i, r = Bx - g its slip)."
        )?;
        writeln!(
            w,
            "Stationarity: Ax - f + B'lambda = 0 over every row. A is symmetric (both triangles stored)."
        )?;
        writeln!(
            w,
            "The box rows are NOT one-sided rows Bx <= g: reading B and g alone (without blocks.csv) states a different problem."
        )?;
    }
    if let BoxBounds::CoulombSnapshot {
        backend,
        tolerance,
        objective,
    } = bounds
    {
        writeln!(
            w,
            "Coulomb friction is not a QP: the bound mu*max(0, lambda_n) of each Coulomb row depends on the answer. These files hold a Tresca snapshot: every Coulomb row bounded by mu*max(0, lambda_n) of the scene's answer ({backend}, solved to tolerance {tolerance:e}, objective {objective:e}), the last Tresca problem of the fixed point. Its solution is that answer; a solver of this QP does not solve the Coulomb problem itself."
        )?;
    }
    if model.path.as_ref().is_some_and(|p| p.increments.len() > 1) {
        writeln!(
            w,
            "The scene has a load path: these files hold its last increment's problem (the whole load and prescribed values), which a frictionless answer does not depend on the path to reach."
        )?;
    }
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
