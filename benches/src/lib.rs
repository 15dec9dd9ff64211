//! Shared set-up of the signorini benches (the benches themselves live in `benches/benches/`).
//!
//! Every bench runs on Experiment 3 with both bodies refined
//! (`fixtures/seed/exp3-both-h0.08.toml`), with `hmax` overridden on both bodies to each of
//! [`HMAX`]; bench names carry the resulting number of DOFs, e.g. `assemble/exp3-both/dofs=2124`.

use std::path::PathBuf;

use signorini::backends::{make_backend, BackendKind};
use signorini_core::mesh::MeshLimits;
use signorini_core::model::{self, Model};
use signorini_core::qp::{QpBackend, QpProblem, SolveOptions};
use signorini_core::scene::Scene;
use signorini_dual::{DualBackend, DualSettings};

/// The `hmax` values benched (2 124, 30 002 and 117 572 free DOFs; 14, 51 and 101 contact rows).
pub const HMAX: [f64; 3] = [0.08, 0.02, 0.01];

/// Name of the scene in bench ids.
pub const SCENE: &str = "exp3-both";

/// Path of the Experiment 3 (both bodies) fixture.
pub fn fixture_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/seed/exp3-both-h0.08.toml")
}

/// Experiment 3 (both bodies) with `hmax` set on every body.
pub fn scene(hmax: f64) -> Scene {
    let mut scene =
        signorini::run::load_scene(Some(&fixture_path())).expect("the exp3-both fixture parses");
    for body in &mut scene.bodies {
        body.hmax = hmax;
    }
    scene
}

/// One benched size: the scene, its model and reduced QP.
#[derive(Debug, Clone)]
pub struct Case {
    /// `hmax` of both bodies.
    pub hmax: f64,
    /// The scene.
    pub scene: Scene,
    /// The assembled model.
    pub model: Model,
    /// The reduced QP (free DOFs only).
    pub qp: QpProblem,
}

impl Case {
    /// Meshes, assembles and reduces Experiment 3 at `hmax`.
    pub fn new(hmax: f64) -> Self {
        let scene = scene(hmax);
        let prepared =
            signorini::run::prepare(&scene, &MeshLimits::default()).expect("exp3-both meshes");
        Self {
            hmax,
            scene,
            model: prepared.model,
            qp: prepared.qp,
        }
    }

    /// Unknowns of the reduced QP (free DOFs of both bodies), the `DOFs` column of
    /// `BENCHMARKS.md`: 2 124, 30 002 and 117 572 at the three [`HMAX`].
    pub fn dofs(&self) -> usize {
        self.qp.dofs()
    }

    /// Bench id suffix, e.g. `exp3-both/dofs=2124`.
    pub fn id(&self) -> String {
        format!("{SCENE}/dofs={}", self.dofs())
    }

    /// Meshes of the scene (what the `assemble` bench consumes).
    pub fn meshes(&self) -> Vec<signorini_core::mesh::Mesh> {
        model::mesh_scene(&self.scene, &MeshLimits::default()).expect("exp3-both meshes")
    }
}

/// The solve options of every `solve/*` bench.
pub fn solve_options() -> SolveOptions {
    SolveOptions {
        tol: 1e-8,
        ..Default::default()
    }
}

/// A backend benched under `solve/<name>`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bench {
    /// One of the driver's backends.
    Driver(BackendKind),
    /// The dual active-set / semismooth Newton method (not selectable in the driver).
    DualSsn,
}

impl Bench {
    /// Every benched backend.
    pub const ALL: [Bench; 5] = [
        Bench::Driver(BackendKind::Clarabel),
        Bench::Driver(BackendKind::Osqp),
        Bench::Driver(BackendKind::DualPgs),
        Bench::Driver(BackendKind::DualUzawa),
        Bench::DualSsn,
    ];

    /// Name in bench ids.
    pub fn name(self) -> &'static str {
        match self {
            Bench::Driver(kind) => kind.name(),
            Bench::DualSsn => "dual-ssn",
        }
    }

    /// A fresh backend with default settings.
    pub fn backend(self) -> Box<dyn QpBackend> {
        match self {
            Bench::Driver(kind) => make_backend(kind).expect("backend compiled in"),
            Bench::DualSsn => Box::new(DualBackend::active_set(DualSettings::default())),
        }
    }
}
