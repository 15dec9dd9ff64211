//! `sweep.csv`: one [`Point`] a row under the header [`COLUMNS`], its strict reading (for
//! `--resume` and `sweep merge`), its lenient reading and its writing.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::output::OutputError;

/// One row of `sweep.csv`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Point {
    /// Swept hmax.
    pub hmax: f64,
    /// Free DOFs.
    pub dofs: usize,
    /// Contact rows.
    pub constraints: usize,
    /// Backend name.
    pub backend: String,
    /// Requested tolerance.
    pub tol: f64,
    /// Core-checked status.
    pub status: String,
    /// Backend iterations.
    pub iterations: usize,
    /// Median meshing time, s.
    pub mesh_s: f64,
    /// Median assembly time, s.
    pub assemble_s: f64,
    /// Median solve time, s.
    pub solve_s: f64,
    /// Median floor (factor + solve of A), s.
    pub floor_s: f64,
    /// solve_s / floor_s.
    pub ratio_to_floor: f64,
    /// max nodal |u − u_ref| / max |u_ref| against the same mesh's reference.
    pub error_vs_reference: Option<f64>,
    /// Relative difference to the finest mesh (max displacement and probes).
    pub error_vs_finest: Option<f64>,
    /// Largest nodal displacement.
    pub max_displacement: f64,
    /// Peak resident memory while the point was solved (model included), MiB.
    pub peak_rss_mb: f64,
    /// Core residual: penetration (length).
    pub max_penetration: f64,
    /// Core residual: stationarity.
    pub stationarity: f64,
    /// Core residual: complementarity.
    pub complementarity: f64,
    /// The backend's own verdict before the core's check.
    pub backend_status: String,
    /// Probe displacements `name:ux:uy` joined by `;`.
    pub probes: String,
    /// [`scene_hash`] of the scene the point was solved for.
    pub scene_hash: String,
    /// Fill-reducing ordering of the floor's factor (`amd` or `metis`).
    pub floor_ordering: String,
    /// Nonzeros of the floor's Cholesky factor L (lower triangle, diagonal included).
    pub floor_nnz_l: usize,
}

/// The header of `sweep.csv`: [`Point`]'s fields in order.
pub const COLUMNS: [&str; 24] = [
    "hmax",
    "dofs",
    "constraints",
    "backend",
    "tol",
    "status",
    "iterations",
    "mesh_s",
    "assemble_s",
    "solve_s",
    "floor_s",
    "ratio_to_floor",
    "error_vs_reference",
    "error_vs_finest",
    "max_displacement",
    "peak_rss_mb",
    "max_penetration",
    "stationarity",
    "complementarity",
    "backend_status",
    "probes",
    "scene_hash",
    "floor_ordering",
    "floor_nnz_l",
];

impl Point {
    /// The point as a row for the plots.
    pub(crate) fn to_row(&self) -> crate::plots::SweepRow {
        crate::plots::SweepRow {
            hmax: self.hmax,
            dofs: self.dofs,
            constraints: self.constraints,
            backend: self.backend.clone(),
            tol: self.tol,
            status: self.status.clone(),
            iterations: self.iterations,
            mesh_s: self.mesh_s,
            assemble_s: self.assemble_s,
            solve_s: self.solve_s,
            floor_s: self.floor_s,
            ratio_to_floor: self.ratio_to_floor,
            error_vs_reference: self.error_vs_reference,
            error_vs_finest: self.error_vs_finest,
            max_displacement: self.max_displacement,
            peak_rss_mb: self.peak_rss_mb,
            max_penetration: self.max_penetration,
            stationarity: self.stationarity,
            complementarity: self.complementarity,
        }
    }
}

/// Reads the points of an existing `sweep.csv`.
pub fn read_points(path: &Path) -> Result<Vec<Point>, OutputError> {
    crate::output::read_csv(path)
}

/// `sweep.csv`'s bytes checked and read row by row, for `--resume` and `sweep merge`: UTF-8
/// text ending in a line break, the header [`COLUMNS`] (a file without `scene_hash`, or with an
/// older version's shorter header, is named as such), every row complete and readable with a
/// status; each row is handed to `row` with its line.  Every refusal is `refuse(line, reason)`
/// (lines from 1); the first one stops the reading.
pub(crate) fn read_rows_strict<E>(
    bytes: Vec<u8>,
    refuse: impl Fn(u64, String) -> E,
    mut row: impl FnMut(u64, Point) -> Result<(), E>,
) -> Result<(), E> {
    let text = String::from_utf8(bytes).map_err(|e| {
        let line = 1 + e.as_bytes()[..e.utf8_error().valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count() as u64;
        refuse(line, "not UTF-8 text".into())
    })?;
    if text.is_empty() {
        return Err(refuse(1, "the file is empty (no header)".into()));
    }
    if !text.ends_with('\n') {
        let line = 1 + text.matches('\n').count() as u64;
        return Err(refuse(
            line,
            "the line is incomplete (no line break at the end of the file)".into(),
        ));
    }
    let mut reader = csv::ReaderBuilder::new().from_reader(text.as_bytes());
    let header = reader
        .headers()
        .map_err(|e| refuse(1, format!("unreadable header: {e}")))?
        .clone();
    if !header.iter().any(|h| h == "scene_hash") {
        return Err(refuse(
            1,
            "no scene_hash column: the file was not written by this version of signorini's sweep"
                .into(),
        ));
    }
    let columns: Vec<&str> = header.iter().collect();
    if columns.len() < COLUMNS.len() && COLUMNS.starts_with(&columns) {
        return Err(refuse(
            1,
            format!(
                "the file was written by an older version of signorini's sweep: its header lacks the last column(s) {}",
                COLUMNS[columns.len()..].join(",")
            ),
        ));
    }
    if !header.iter().eq(COLUMNS.iter().copied()) {
        return Err(refuse(
            1,
            format!(
                "the header is not sweep.csv's: expected {}",
                COLUMNS.join(",")
            ),
        ));
    }
    let mut record = csv::StringRecord::new();
    loop {
        let more = reader.read_record(&mut record).map_err(|e| {
            let line = e.position().map_or(0, csv::Position::line);
            match e.kind() {
                csv::ErrorKind::UnequalLengths {
                    expected_len, len, ..
                } => refuse(
                    line,
                    format!("{len} fields, but the header has {expected_len}"),
                ),
                _ => refuse(line, e.to_string()),
            }
        })?;
        if !more {
            return Ok(());
        }
        let line = record.position().map_or(0, csv::Position::line);
        let p: Point = record
            .deserialize(Some(&header))
            .map_err(|e| refuse(line, format!("unreadable row: {e}")))?;
        if p.status.trim().is_empty() {
            return Err(refuse(line, "empty status".into()));
        }
        row(line, p)?;
    }
}

/// Writes `points` as `sweep.csv` (header first, even without points).
pub(crate) fn write_csv(w: &mut dyn std::io::Write, points: &[Point]) -> std::io::Result<()> {
    let mut csv = csv::WriterBuilder::new().has_headers(false).from_writer(w);
    csv.write_record(COLUMNS)?;
    for p in points {
        csv.serialize(p).map_err(std::io::Error::other)?;
    }
    csv.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_header_is_the_points_fields() {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.serialize(Point {
            hmax: 0.1,
            dofs: 1,
            constraints: 1,
            backend: "b".into(),
            tol: 1e-9,
            status: "solved".into(),
            backend_status: "solved".into(),
            iterations: 1,
            mesh_s: 0.0,
            assemble_s: 0.0,
            solve_s: 0.0,
            floor_s: 0.0,
            ratio_to_floor: 0.0,
            error_vs_reference: None,
            error_vs_finest: None,
            max_displacement: 0.0,
            peak_rss_mb: 0.0,
            max_penetration: 0.0,
            stationarity: 0.0,
            complementarity: 0.0,
            probes: String::new(),
            scene_hash: String::new(),
            floor_ordering: "amd".into(),
            floor_nnz_l: 1,
        })
        .unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        assert_eq!(text.lines().next().unwrap(), COLUMNS.join(","));
    }
}
