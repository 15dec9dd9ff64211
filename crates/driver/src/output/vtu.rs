//! VTK XML UnstructuredGrid (`.vtu`, ASCII) writer.

use std::fmt::LowerExp;
use std::io::{self, Write};
use std::path::Path;

use signorini_core::mesh::Cells;

use super::{validate, write_atomically, BodyField, OutputError};

/// VTK cell type of a linear triangle.
const VTK_TRIANGLE: u8 = 5;
/// VTK cell type of a bilinear quadrilateral.
const VTK_QUAD: u8 = 9;

/// Writes every body into ONE VTK XML UnstructuredGrid (ASCII), so ParaView shows the whole scene
/// at once.  Bodies are concatenated in the given order: body `k`'s nodes and cells follow those
/// of bodies `0..k`.
///
/// * Points: `(x, y, 0)`, Float64.
/// * Cells: `VTK_TRIANGLE` (5) or `VTK_QUAD` (9), counter-clockwise; connectivity and offsets
///   Int64, types UInt8.
/// * PointData: `displacement` (Float64, 3 components, z = 0), `contact_pressure` (Float64),
///   `body_id` (Int32, index into `bodies`).
/// * CellData: `stress` (Float64, 6-component symmetric tensor in VTK's order
///   `XX, YY, ZZ, XY, YZ, XZ`, i.e. `σxx, σyy, σzz, σxy, 0, 0`), `von_mises` (Float64),
///   `body_id` (Int32).
///
/// An XML comment at the top lists `body_id → name`.  Floats are written with `{:e}`, the
/// shortest representation that reads back to the same `f64`.
///
/// Lengths are validated first; on [`OutputError::Mismatch`] no file is written.
pub fn write_vtu(path: &Path, bodies: &[BodyField]) -> Result<(), OutputError> {
    validate(bodies)?;
    write_atomically(path, |w| write_grid(w, bodies))
}

/// The document of [`write_vtu`], written to `w` (for an [`OutputSet`](crate::outdir::OutputSet)).
/// Lengths are validated first; a mismatch is an [`io::ErrorKind::InvalidData`] error carrying
/// the [`OutputError::Mismatch`] message, and nothing is written.
pub fn write_vtu_to(w: &mut dyn Write, bodies: &[BodyField]) -> io::Result<()> {
    validate(bodies).map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e.to_string()))?;
    write_grid(w, bodies)
}

/// Writes a whitespace-separated list of floats (round-trip `{:e}`), `per_line` to a line.
fn write_list<T: LowerExp>(
    w: &mut dyn Write,
    values: impl IntoIterator<Item = T>,
    per_line: usize,
) -> io::Result<()> {
    write_items(w, values, per_line, |w, v| write!(w, "{v:e}"))
}

/// Writes a whitespace-separated list of integers.
fn write_ints<T: std::fmt::Display>(
    w: &mut dyn Write,
    values: impl IntoIterator<Item = T>,
    per_line: usize,
) -> io::Result<()> {
    write_items(w, values, per_line, |w, v| write!(w, "{v}"))
}

/// Writes items `per_line` to a line, indented, each with `put`.
fn write_items<T>(
    w: &mut dyn Write,
    values: impl IntoIterator<Item = T>,
    per_line: usize,
    mut put: impl FnMut(&mut dyn Write, T) -> io::Result<()>,
) -> io::Result<()> {
    for (i, v) in values.into_iter().enumerate() {
        let sep = if i == 0 {
            "          "
        } else if i % per_line == 0 {
            "\n          "
        } else {
            " "
        };
        w.write_all(sep.as_bytes())?;
        put(w, v)?;
    }
    writeln!(w)
}

/// Opens a `DataArray` element.
fn open_array(w: &mut dyn Write, ty: &str, name: &str, components: usize) -> io::Result<()> {
    open_named_array(w, ty, name, components, &[])
}

/// Opens a `DataArray` element whose components carry names (shown by ParaView).
fn open_named_array(
    w: &mut dyn Write,
    ty: &str,
    name: &str,
    components: usize,
    component_names: &[&str],
) -> io::Result<()> {
    write!(
        w,
        r#"        <DataArray type="{ty}" Name="{name}" NumberOfComponents="{components}""#
    )?;
    for (i, c) in component_names.iter().enumerate() {
        write!(w, r#" ComponentName{i}="{c}""#)?;
    }
    writeln!(w, r#" format="ascii">"#)
}

/// Closes a `DataArray` element.
fn close_array(w: &mut dyn Write) -> io::Result<()> {
    writeln!(w, "        </DataArray>")
}

/// Makes `s` safe inside an XML comment: characters XML does not allow become U+FFFD (as
/// everywhere in the output, see [`xml_sanitize`](super::xml_sanitize)), a space separates the
/// hyphens of `--` and follows a trailing `-`, and line breaks become spaces (one name per
/// line).  `& < > " '` need no escaping in a comment and are kept as they are.
fn comment_safe(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in super::xml_sanitize(s).chars() {
        if c == '-' && out.ends_with('-') {
            out.push(' ');
        }
        out.push(if matches!(c, '\n' | '\r') { ' ' } else { c });
    }
    if out.ends_with('-') {
        out.push(' ');
    }
    out
}

/// The XML content (assumes validated input).
fn write_grid(w: &mut dyn Write, bodies: &[BodyField]) -> io::Result<()> {
    let n_points: usize = bodies.iter().map(|b| b.mesh.nodes.len()).sum();
    let n_cells: usize = bodies.iter().map(|b| b.mesh.cells.len()).sum();
    let body_ids = |per: fn(&BodyField) -> usize| {
        bodies
            .iter()
            .enumerate()
            .flat_map(move |(k, b)| std::iter::repeat_n(k as i32, per(b)))
    };

    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(w, "<!-- signorini solution; body_id:")?;
    for (k, b) in bodies.iter().enumerate() {
        writeln!(w, "       {k} = {}", comment_safe(b.name))?;
    }
    writeln!(w, "-->")?;
    writeln!(
        w,
        r#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">"#
    )?;
    writeln!(w, "  <UnstructuredGrid>")?;
    writeln!(
        w,
        r#"    <Piece NumberOfPoints="{n_points}" NumberOfCells="{n_cells}">"#
    )?;

    // Points.
    writeln!(w, "      <Points>")?;
    open_array(w, "Float64", "Points", 3)?;
    write_list(
        w,
        bodies
            .iter()
            .flat_map(|b| b.mesh.nodes.iter().flat_map(|p| [p[0], p[1], 0.0])),
        3,
    )?;
    close_array(w)?;
    writeln!(w, "      </Points>")?;

    // Cells.
    writeln!(w, "      <Cells>")?;
    open_array(w, "Int64", "connectivity", 1)?;
    let mut first = 0usize;
    let mut conn = Vec::new();
    for b in bodies {
        for i in 0..b.mesh.cells.len() {
            conn.extend(b.mesh.cells.cell(i).iter().map(|&n| n + first));
        }
        first += b.mesh.nodes.len();
    }
    write_ints(w, &conn, 12)?;
    close_array(w)?;
    open_array(w, "Int64", "offsets", 1)?;
    let mut end = 0usize;
    let offsets = bodies.iter().flat_map(|b| {
        let per = match b.mesh.cells {
            Cells::Triangles(_) => 3,
            Cells::Quads(_) => 4,
        };
        std::iter::repeat_n(per, b.mesh.cells.len())
    });
    write_ints(
        w,
        offsets.map(|per| {
            end += per;
            end
        }),
        12,
    )?;
    close_array(w)?;
    open_array(w, "UInt8", "types", 1)?;
    write_ints(
        w,
        bodies.iter().flat_map(|b| {
            let ty = match b.mesh.cells {
                Cells::Triangles(_) => VTK_TRIANGLE,
                Cells::Quads(_) => VTK_QUAD,
            };
            std::iter::repeat_n(ty, b.mesh.cells.len())
        }),
        24,
    )?;
    close_array(w)?;
    writeln!(w, "      </Cells>")?;

    // Point data.
    writeln!(
        w,
        r#"      <PointData Vectors="displacement" Scalars="contact_pressure">"#
    )?;
    open_array(w, "Float64", "displacement", 3)?;
    write_list(
        w,
        bodies
            .iter()
            .flat_map(|b| b.displacement.iter().flat_map(|u| [u[0], u[1], 0.0])),
        3,
    )?;
    close_array(w)?;
    open_array(w, "Float64", "contact_pressure", 1)?;
    write_list(
        w,
        bodies
            .iter()
            .flat_map(|b| b.contact_pressure.iter().copied()),
        6,
    )?;
    close_array(w)?;
    open_array(w, "Int32", "body_id", 1)?;
    write_ints(w, body_ids(|b| b.mesh.nodes.len()), 24)?;
    close_array(w)?;
    writeln!(w, "      </PointData>")?;

    // Cell data.
    writeln!(
        w,
        r#"      <CellData Tensors="stress" Scalars="von_mises">"#
    )?;
    open_named_array(
        w,
        "Float64",
        "stress",
        6,
        &["XX", "YY", "ZZ", "XY", "YZ", "XZ"],
    )?;
    write_list(
        w,
        bodies.iter().flat_map(|b| {
            b.stress
                .iter()
                .flat_map(|s| [s[0], s[1], s[3], s[2], 0.0, 0.0])
        }),
        6,
    )?;
    close_array(w)?;
    open_array(w, "Float64", "von_mises", 1)?;
    write_list(
        w,
        bodies.iter().flat_map(|b| b.von_mises.iter().copied()),
        6,
    )?;
    close_array(w)?;
    open_array(w, "Int32", "body_id", 1)?;
    write_ints(w, body_ids(|b| b.mesh.cells.len()), 24)?;
    close_array(w)?;
    writeln!(w, "      </CellData>")?;

    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")
}
