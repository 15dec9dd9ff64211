//! Output files: VTK XML meshes with fields, SVG plots, written atomically.
//!
//! A single file goes through [`write_atomically`]: it is written to a temporary file in the
//! target directory and renamed over the target only when the whole content was written, so a
//! failed run never leaves a truncated file (or a stray temporary file) behind.  The files of one
//! command are written together as an [`OutputSet`](crate::outdir::OutputSet) instead (see
//! [`crate::outdir`]); the writers here therefore also come as functions that write to any
//! `Write` or return the document ([`write_vtu_to`], [`render_deformed_svg`]).
//!
//! * [`write_vtu`] writes one VTK XML UnstructuredGrid holding every body, zlib-compressed
//!   binary by default or ASCII ([`VtuFormat`], [`write_vtu_with`]; see its docs for the arrays
//!   and their layout).
//! * [`write_deformed_svg`] plots the undeformed and the magnified deformed meshes; the factor is
//!   chosen by [`magnification`].
//! * [`render_pressure_svg`] plots the contact pressure against the arc coordinate along each
//!   pair's slave interface, from the report (see [`pressure`]).
//!
//! Text from the scene (title, body names) may hold anything: in every XML file it is escaped
//! ([`xml_escape`]) and characters XML 1.0 does not allow are replaced by U+FFFD
//! ([`xml_sanitize`]), so the files are always well-formed.

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use signorini_core::mesh::Mesh;

pub(crate) mod chart_style;
pub mod pressure;
pub(crate) mod svg;
mod vtu;

#[cfg(test)]
mod tests;

pub use pressure::render_pressure_svg;
pub use svg::{magnification, render_deformed_svg, write_deformed_svg};
pub use vtu::{write_vtu, write_vtu_to, write_vtu_to_with, write_vtu_with, VtuFormat};

/// One body's fields for output.
#[derive(Debug, Clone, Copy)]
pub struct BodyField<'a> {
    /// Body name (from the scene).
    pub name: &'a str,
    /// The body's mesh.
    pub mesh: &'a Mesh,
    /// Displacement per node.
    pub displacement: &'a [[f64; 2]],
    /// Stress per cell: σxx, σyy, σxy, σzz (σzz ≠ 0 in plane strain).
    pub stress: &'a [[f64; 4]],
    /// Von Mises stress per cell.
    pub von_mises: &'a [f64],
    /// Contact pressure per node (0 away from contact).
    pub contact_pressure: &'a [f64],
    /// Tangential traction, slip and state per node, when the model has friction (then for
    /// every body).
    pub friction: Option<&'a signorini_core::report::FrictionField>,
}

impl<'a> BodyField<'a> {
    /// The views of every body of a solve, in order: its mesh, its fields, its scene entry
    /// (the name).
    pub fn of_bodies(
        meshes: &'a [Mesh],
        fields: &'a [signorini_core::report::BodyFields],
        bodies: &'a [signorini_core::scene::Body],
    ) -> Vec<Self> {
        meshes
            .iter()
            .zip(fields)
            .zip(bodies)
            .map(|((mesh, f), body)| BodyField {
                name: &body.name,
                mesh,
                displacement: &f.displacement,
                stress: &f.stress,
                von_mises: &f.von_mises,
                contact_pressure: &f.contact_pressure,
                friction: f.friction.as_ref(),
            })
            .collect()
    }
}

/// Failure to write an output file.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The file (or its temporary sibling) could not be created, written or renamed.
    #[error("cannot write {}", path.display())]
    Io {
        /// The file that was to be written.
        path: PathBuf,
        /// The underlying error.
        source: io::Error,
    },
    /// A field's length disagrees with the mesh (or a cell names a node that does not exist).
    #[error("inconsistent output data: {0}")]
    Mismatch(String),
    /// The plotting library failed.
    #[error("plotting failed: {0}")]
    Plot(String),
    /// Another run holds the output directory's lock (see [`crate::outdir::DirLock`]).
    #[error("{} is in use by another signorini run (it holds the directory's lock); wait for that run to finish or choose another output directory", dir.display())]
    Locked {
        /// The output directory.
        dir: PathBuf,
    },
}

/// Whether XML 1.0 allows the character `c` in a document: tab, newline, carriage return and
/// everything from U+0020 on except U+FFFE and U+FFFF (Rust `char`s are never surrogates).
fn xml_allowed(c: char) -> bool {
    matches!(c, '\t' | '\n' | '\r') || (c >= ' ' && c != '\u{FFFE}' && c != '\u{FFFF}')
}

/// `text` with every character XML 1.0 does not allow (control characters other than tab,
/// newline and carriage return; U+FFFE; U+FFFF) replaced by U+FFFD, nothing else changed.
/// For text handed to a library that escapes `& < > " '` itself (plotters' SVG backend).
pub fn xml_sanitize(text: &str) -> String {
    text.chars()
        .map(|c| if xml_allowed(c) { c } else { '\u{FFFD}' })
        .collect()
}

/// `text` ready for XML character data or a quoted attribute value: [`xml_sanitize`]d, and
/// `&`, `<`, `>`, `"`, `'` written as entity references.
pub fn xml_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if xml_allowed(c) => out.push(c),
            _ => out.push('\u{FFFD}'),
        }
    }
    out
}

/// Reads the rows of the CSV file at `path` (with a header) as `T`s: [`OutputError::Io`] when
/// it cannot be opened, [`OutputError::Mismatch`] naming the row for one that does not read.
pub fn read_csv<T: serde::de::DeserializeOwned>(path: &Path) -> Result<Vec<T>, OutputError> {
    let mut reader = csv::Reader::from_path(path).map_err(|e| OutputError::Io {
        path: path.to_path_buf(),
        source: io::Error::other(e),
    })?;
    reader
        .deserialize()
        .enumerate()
        .map(|(i, r)| {
            r.map_err(|e| OutputError::Mismatch(format!("{}: row {}: {e}", path.display(), i + 2)))
        })
        .collect()
}

/// Writes `path` atomically: `write` fills a temporary file in the same directory, which is then
/// renamed over `path`.  If `write` (or flushing, or the rename) fails, neither a partial `path`
/// nor the temporary file is left behind, and an existing `path` is left untouched.
///
/// The writer handed to `write` is buffered.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), OutputError> {
    let io_err = |source: io::Error| OutputError::Io {
        path: path.to_path_buf(),
        source,
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".signorini-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // NamedTempFile defaults to 0600; output files are ordinary readable files.
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    let tmp = builder.tempfile_in(dir).map_err(io_err)?;
    {
        let mut out = BufWriter::new(tmp.as_file());
        write(&mut out).map_err(io_err)?;
        out.flush().map_err(io_err)?;
    }
    // On error the temporary file is dropped, which deletes it.
    tmp.persist(path).map_err(|e| io_err(e.error))?;
    Ok(())
}

/// Checks that every field of every body has the length its mesh asks for and that every cell
/// refers to existing nodes ([`OutputError::Mismatch`] otherwise).  [`write_vtu`],
/// [`write_vtu_to`], [`write_deformed_svg`] and [`render_deformed_svg`] call it first.
pub fn check_fields(bodies: &[BodyField]) -> Result<(), OutputError> {
    validate(bodies)
}

/// See [`check_fields`].
fn validate(bodies: &[BodyField]) -> Result<(), OutputError> {
    for b in bodies {
        let nodes = b.mesh.nodes.len();
        let cells = b.mesh.cells.len();
        let check = |field: &str, len: usize, want: usize, what: &str| {
            if len == want {
                Ok(())
            } else {
                Err(OutputError::Mismatch(format!(
                    "body \"{}\": {field} has {len} entries but the mesh has {want} {what}",
                    b.name
                )))
            }
        };
        check("displacement", b.displacement.len(), nodes, "nodes")?;
        check("contact_pressure", b.contact_pressure.len(), nodes, "nodes")?;
        if let Some(f) = b.friction {
            check(
                "tangential_traction",
                f.tangential_traction.len(),
                nodes,
                "nodes",
            )?;
            check("slip", f.slip.len(), nodes, "nodes")?;
            check("contact_state", f.state.len(), nodes, "nodes")?;
        }
        check("stress", b.stress.len(), cells, "cells")?;
        check("von_mises", b.von_mises.len(), cells, "cells")?;
        for i in 0..cells {
            if let Some(&n) = b.mesh.cells.cell(i).iter().find(|&&n| n >= nodes) {
                return Err(OutputError::Mismatch(format!(
                    "body \"{}\": cell {i} refers to node {n} but the mesh has {nodes} nodes",
                    b.name
                )));
            }
        }
        if let Some(e) = b
            .mesh
            .boundary
            .iter()
            .find(|e| e[0] >= nodes || e[1] >= nodes)
        {
            return Err(OutputError::Mismatch(format!(
                "body \"{}\": boundary edge {e:?} refers to a node beyond the mesh's {nodes} nodes",
                b.name
            )));
        }
    }
    Ok(())
}
