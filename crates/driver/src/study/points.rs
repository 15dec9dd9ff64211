//! The points of a study (`study.csv`'s rows) and the error measures read from them: the data
//! [`super`] writes and [`super::plot`] draws, apart from both so that the plot does
//! not import the study that calls it.

use serde::{Deserialize, Serialize};

/// One row of `study.csv`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct StudyPoint {
    /// `node-to-segment` or `mortar`.
    pub formulation: String,
    /// `uniform` or `graded`.
    pub mesh: String,
    /// `p1` or `q1` (of the rectangular bodies).
    pub element: String,
    /// The coarsest body's hmax.
    pub hmax: f64,
    /// The smallest element size asked anywhere (bodies and refine regions).
    pub hmin: f64,
    /// Free DOFs (0 when meshing failed).
    pub dofs: usize,
    /// Contact rows.
    pub constraints: usize,
    /// Backend (for `auto`: the one whose answer is written).
    pub backend: String,
    /// Core-checked status, or `error` when meshing, assembly or the solve stopped.
    pub status: String,
    /// Meshing, s.
    pub mesh_s: f64,
    /// Assembly, s.
    pub assemble_s: f64,
    /// Solve, s.
    pub solve_s: f64,
    /// mesh_s + assemble_s + solve_s.
    pub total_s: f64,
    /// Hertz half-width from the second moment of the nodal forces.
    pub half_width: Option<f64>,
    /// half_width / reference − 1.
    pub error_half_width: Option<f64>,
    /// Hertz peak pressure from the elliptical fit of the inner half.
    pub peak_pressure: Option<f64>,
    /// peak_pressure / reference − 1.
    pub error_peak_pressure: Option<f64>,
    /// The largest nodal pressure.
    pub peak_nodal_pressure: Option<f64>,
    /// peak_nodal_pressure / reference p₀ − 1.
    pub error_peak_nodal_pressure: Option<f64>,
    /// Patch test: max |pⱼ / p − 1| over the slave nodes in contact.
    pub pressure_deviation: Option<f64>,
    /// Cattaneo–Mindlin stick half-width c from the second moment of μλₙ − λₜ.
    #[serde(default)]
    pub stick_half_width: Option<f64>,
    /// stick_half_width / (a √(1 − |Q|/(μP))) − 1.
    #[serde(default)]
    pub error_stick_half_width: Option<f64>,
    /// Cattaneo–Mindlin: rms relative error of the tangential traction over |x| < a.
    #[serde(default)]
    pub error_tangential_traction: Option<f64>,
    /// Why the point is not solved (empty when it is).
    pub message: String,
}

/// The header of `study.csv`: [`StudyPoint`]'s fields in order.
pub const COLUMNS: [&str; 24] = [
    "formulation",
    "mesh",
    "element",
    "hmax",
    "hmin",
    "dofs",
    "constraints",
    "backend",
    "status",
    "mesh_s",
    "assemble_s",
    "solve_s",
    "total_s",
    "half_width",
    "error_half_width",
    "peak_pressure",
    "error_peak_pressure",
    "peak_nodal_pressure",
    "error_peak_nodal_pressure",
    "pressure_deviation",
    "stick_half_width",
    "error_stick_half_width",
    "error_tangential_traction",
    "message",
];

impl StudyPoint {
    /// `formulation, mesh, element`.
    pub fn combination(&self) -> String {
        format!("{}, {}, {}", self.formulation, self.mesh, self.element)
    }

    /// Whether the point is solved.
    pub fn solved(&self) -> bool {
        self.status == "solved"
    }
}

/// The error measures of a study, as (name, CSV column reader).
pub type Measure = (&'static str, fn(&StudyPoint) -> Option<f64>);

/// The error measures drawn and fitted, in panel order.
pub const MEASURES: [Measure; 6] = [
    ("half-width a", |p| p.error_half_width),
    ("peak pressure p0 (elliptical fit)", |p| {
        p.error_peak_pressure
    }),
    ("peak pressure p0 (max nodal)", |p| {
        p.error_peak_nodal_pressure
    }),
    ("patch test max |p/p_ref - 1|", |p| p.pressure_deviation),
    ("stick half-width c (Cattaneo)", |p| {
        p.error_stick_half_width
    }),
    ("tangential q, rms (Cattaneo)", |p| {
        p.error_tangential_traction
    }),
];

/// Combinations in order of first appearance.
pub fn combination_order(points: &[StudyPoint]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for p in points {
        let c = p.combination();
        if !names.contains(&c) {
            names.push(c);
        }
    }
    names
}
