//! The process's exit codes, one per kind of outcome, and the classification of errors into them.
//!
//! | code | meaning |
//! |---|---|
//! | 0 | every solve asked for is `solved` (or `check` found the scene valid) |
//! | 1 | bad input or usage: the scene (or its path), a flag or an argument is refused; nothing was written |
//! | 2 | not solved: the run finished and wrote its results, but a status is not `solved` |
//! | 3 | I/O or resource error: a file could not be read or written, the output directory is in use, or the scene would need more elements or memory than allowed |
//!
//! Each error type says its own code through [`ExitClass`]; [`classify`] asks every cause of an
//! error's chain, in order, through one table of downcasters ([`CAUSES`]), and the first cause
//! that decides wins (1 when none does).  The types and what they decide:
//!
//! | error type | decides |
//! |---|---|
//! | `SceneError`, `SuiteError`, `BaselineError` | 1: a scene, suite directory or baseline that cannot be read is the user's input |
//! | `std::io::Error`, `OutputError`, [`Resource`], `PreflightError` | 3 |
//! | `QpError` | 3 when `TooLarge` (a backend's memory refusal), else its causes decide |
//! | `SolveError` | as its `Qp` error, else its causes decide |
//! | `MeshError` | 3 when `TooManyElements`, else its causes decide |
//! | `RunError` | as its scene, preflight, solve or output error, or a mesh error of its model; else its causes decide |
//! | `SweepError` | 3 for its output error and for a run error that decides 3, else its causes decide |
//! | `MergeError` | 3 for its output error, else its causes decide |
//! | `FclibError` | 1 for a scene FCLIB cannot state (Tresca, sizes past 32 bits) and a file that cannot be read or states what our QP cannot, else 3 |
//!
//! Adding an error type is one [`ExitClass`] impl here (a name in `always!` when it always
//! decides the same code) plus one entry in [`CAUSES`].

use std::error::Error;
use std::process::ExitCode;

use signorini_core::mesh::MeshError;
use signorini_core::model::ModelError;
use signorini_core::preflight::PreflightError;
use signorini_core::qp::QpError;
use signorini_core::scene::SceneError;
use signorini_core::solve::SolveError;

use crate::fclib::FclibError;
use crate::output::OutputError;
use crate::run::RunError;
use crate::suite::baseline::BaselineError;
use crate::suite::SuiteError;
use crate::sweep::merge::MergeError;
use crate::sweep::SweepError;

/// What a command ended with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Exit {
    /// Everything asked for was solved (or is valid).
    Success = 0,
    /// Bad input or usage.
    Input = 1,
    /// A run finished but not every status is `solved`.
    NotSolved = 2,
    /// I/O or resource error.
    Resource = 3,
}

impl From<Exit> for ExitCode {
    fn from(e: Exit) -> Self {
        ExitCode::from(e as u8)
    }
}

/// The exit code an error type decides for itself.
pub trait ExitClass {
    /// The code this error decides, or `None` to leave it to the next cause of the chain.
    fn exit(&self) -> Option<Exit>;
}

/// Asks `cause` as an `E`: `None` when it is not one, or when it decides nothing.
fn ask<E: ExitClass + Error + 'static>(cause: &(dyn Error + 'static)) -> Option<Exit> {
    cause.downcast_ref::<E>().and_then(E::exit)
}

/// A downcaster: the code `cause` decides when it is of the entry's type.
pub type Downcaster = fn(&(dyn Error + 'static)) -> Option<Exit>;

/// Every error type that decides an exit code (see the module doc's table).
pub const CAUSES: &[Downcaster] = &[
    ask::<SceneError>,
    ask::<SuiteError>,
    ask::<BaselineError>,
    ask::<std::io::Error>,
    ask::<OutputError>,
    ask::<Resource>,
    ask::<PreflightError>,
    ask::<QpError>,
    ask::<SolveError>,
    ask::<MeshError>,
    ask::<RunError>,
    ask::<SweepError>,
    ask::<MergeError>,
    ask::<FclibError>,
];

/// The exit code an error deserves: the code decided by the first cause in its chain that
/// decides one ([`CAUSES`]), else [`Exit::Input`].
pub fn classify(error: &anyhow::Error) -> Exit {
    error
        .chain()
        .find_map(|cause| CAUSES.iter().find_map(|ask| ask(cause)))
        .unwrap_or(Exit::Input)
}

/// An error that is about the machine's resources rather than the input (exit code 3).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Resource(pub String);

/// Implements [`ExitClass`] for error types that always decide `$code`.
macro_rules! always {
    ($code:expr => $($ty:ty),+) => {
        $(impl ExitClass for $ty {
            fn exit(&self) -> Option<Exit> {
                Some($code)
            }
        })+
    };
}

// A scene, suite directory or baseline that cannot be read is the user's input (a wrong
// path), not the machine's.
always!(Exit::Input => SceneError, SuiteError, BaselineError);
always!(Exit::Resource => std::io::Error, OutputError, Resource, PreflightError);

/// A scene FCLIB cannot state is the user's input; a file HDF5 could not write, the machine's.
impl ExitClass for FclibError {
    fn exit(&self) -> Option<Exit> {
        Some(match self {
            FclibError::Tresca { .. }
            | FclibError::LoadPath
            | FclibError::TooLarge { .. }
            | FclibError::Read { .. }
            | FclibError::Format { .. } => Exit::Input,
            FclibError::Rows { .. } | FclibError::Hdf5 { .. } | FclibError::Io { .. } => {
                Exit::Resource
            }
        })
    }
}

/// A backend's memory refusal (a KKT factor, a dense H) is the machine's limit.
impl ExitClass for QpError {
    fn exit(&self) -> Option<Exit> {
        matches!(self, QpError::TooLarge { .. }).then_some(Exit::Resource)
    }
}

impl ExitClass for SolveError {
    fn exit(&self) -> Option<Exit> {
        match self {
            SolveError::Qp(e) => e.exit(),
            _ => None,
        }
    }
}

impl ExitClass for MeshError {
    fn exit(&self) -> Option<Exit> {
        matches!(self, MeshError::TooManyElements { .. }).then_some(Exit::Resource)
    }
}

/// `transparent` errors forward `source()` past their inner error, so the variants ask their
/// inner error themselves.
impl ExitClass for RunError {
    fn exit(&self) -> Option<Exit> {
        match self {
            RunError::Scene(e) => e.exit(),
            RunError::Preflight(e) => e.exit(),
            RunError::Solve(e) => e.exit(),
            RunError::Output(e) => e.exit(),
            RunError::Model(ModelError::Mesh { source, .. }) => source.exit(),
            RunError::Model(_) | RunError::NoContact(_) => None,
        }
    }
}

impl ExitClass for SweepError {
    fn exit(&self) -> Option<Exit> {
        match self {
            SweepError::Output(e) => e.exit(),
            // Only a run's resource errors: a scene error met through a sweep leaves the
            // code to the causes after it, as it always has.
            SweepError::Run(e) => e.exit().filter(|&code| code == Exit::Resource),
            SweepError::Plan(_) | SweepError::Exists(_) | SweepError::Resume { .. } => None,
        }
    }
}

impl ExitClass for MergeError {
    fn exit(&self) -> Option<Exit> {
        match self {
            MergeError::Output(e) => e.exit(),
            MergeError::Refused { .. } | MergeError::Exists(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    #[test]
    fn io_errors_anywhere_in_the_chain_are_resource_errors() {
        let e = anyhow::Error::new(std::io::Error::other("disk full")).context("writing x");
        assert_eq!(classify(&e), Exit::Resource);
        let e = anyhow::anyhow!("--tol must lie in (0, 1)");
        assert_eq!(classify(&e), Exit::Input);
        let locked = OutputError::Locked {
            dir: std::path::PathBuf::from("out"),
        };
        let e = anyhow::Error::new(SweepError::Output(locked));
        assert_eq!(
            classify(&e),
            Exit::Resource,
            "a locked directory, through the sweep"
        );
        let e = anyhow::Error::new(SweepError::Plan("bad".into()));
        assert_eq!(classify(&e), Exit::Input);
        let e = anyhow::Error::new(Resource("too big".into()));
        assert_eq!(classify(&e), Exit::Resource);
        // A scene file that cannot be read is bad input, though its cause is an I/O error.
        let missing =
            signorini_core::scene::Scene::from_path(std::path::Path::new("/nonexistent.toml"));
        let e = anyhow::Error::new(missing.unwrap_err());
        assert_eq!(classify(&e), Exit::Input);
    }

    fn scene_error() -> SceneError {
        signorini_core::scene::Scene::from_path(std::path::Path::new("/nonexistent.toml"))
            .unwrap_err()
    }

    fn too_large() -> QpError {
        QpError::TooLarge {
            backend: "clarabel",
            what: "the KKT factor".into(),
            needed: 2.0,
            available: 1.0,
        }
    }

    fn too_many_elements() -> MeshError {
        MeshError::TooManyElements {
            estimated: 10,
            limit: 1,
        }
    }

    fn locked() -> OutputError {
        OutputError::Locked {
            dir: PathBuf::from("out"),
        }
    }

    /// One error of every type in [`CAUSES`], each deciding, with the code the module doc's
    /// table gives it (the expected values are that table's, row by row).
    fn deciding_samples() -> Vec<(anyhow::Error, Exit)> {
        let not_json = serde_json::from_str::<u8>("x").unwrap_err();
        vec![
            (scene_error().into(), Exit::Input),
            (SuiteError::Empty(PathBuf::from("s")).into(), Exit::Input),
            (
                BaselineError::Parse {
                    path: PathBuf::from("suite.json"),
                    source: not_json,
                }
                .into(),
                Exit::Input,
            ),
            (std::io::Error::other("disk full").into(), Exit::Resource),
            (locked().into(), Exit::Resource),
            (Resource("too big".into()).into(), Exit::Resource),
            (
                PreflightError::Analysis("no memory".into()).into(),
                Exit::Resource,
            ),
            (too_large().into(), Exit::Resource),
            (SolveError::Qp(too_large()).into(), Exit::Resource),
            (too_many_elements().into(), Exit::Resource),
            (RunError::Scene(scene_error()).into(), Exit::Input),
            (RunError::Output(locked()).into(), Exit::Resource),
            (
                RunError::Model(ModelError::Mesh {
                    body: "b".into(),
                    source: too_many_elements(),
                })
                .into(),
                Exit::Resource,
            ),
            (
                RunError::Solve(SolveError::Qp(too_large())).into(),
                Exit::Resource,
            ),
            (
                SweepError::Run(RunError::Output(locked())).into(),
                Exit::Resource,
            ),
            (SweepError::Output(locked()).into(), Exit::Resource),
            (MergeError::Output(locked()).into(), Exit::Resource),
            (FclibError::LoadPath.into(), Exit::Input),
            (FclibError::Tresca { pair: 1 }.into(), Exit::Input),
            (
                FclibError::Format {
                    path: "p.hdf5".into(),
                    reason: "spacedim = 3".into(),
                }
                .into(),
                Exit::Input,
            ),
            (
                FclibError::Io {
                    path: "p.hdf5".into(),
                    source: std::io::Error::other("disk full"),
                }
                .into(),
                Exit::Resource,
            ),
        ]
    }

    #[test]
    fn every_error_type_in_the_table_maps_as_documented() {
        let samples = deciding_samples();
        for (error, expected) in &samples {
            assert_eq!(classify(error), *expected, "{error:?}");
        }
        for (i, ask) in CAUSES.iter().enumerate() {
            assert!(
                samples
                    .iter()
                    .any(|(e, _)| e.chain().next().is_some_and(|c| ask(c).is_some())),
                "entry {i} of CAUSES has no sample deciding through it"
            );
        }
    }

    #[test]
    fn variants_that_decide_nothing_leave_the_code_to_their_causes() {
        // Expected values from the module doc: these variants decide nothing, so an error
        // whose chain has no deciding cause is bad input (1).
        let undecided: Vec<anyhow::Error> = vec![
            QpError::Dimensions("x".into()).into(),
            MeshError::NotARectangle.into(),
            RunError::NoContact("scene".into()).into(),
            SweepError::Plan("bad".into()).into(),
            SweepError::Exists(PathBuf::from("sweep.csv")).into(),
            MergeError::Exists(PathBuf::from("sweep.csv")).into(),
        ];
        for e in &undecided {
            assert_eq!(classify(e), Exit::Input, "{e:?}");
        }
        // A scene error through a sweep does not decide 1 itself (only a run's resource errors
        // do): both wrappers are `transparent`, so the next cause is the unreadable file's I/O
        // error, which decides 3 — the mapping as it stood before the table.
        let e = anyhow::Error::new(SweepError::Run(RunError::Scene(scene_error())));
        assert_eq!(classify(&e), Exit::Resource);
    }
}
