//! The process's exit codes, one per kind of outcome, and the classification of errors into them.
//!
//! | code | meaning |
//! |---|---|
//! | 0 | every solve asked for is `solved` (or `check` found the scene valid) |
//! | 1 | bad input or usage: the scene (or its path), a flag or an argument is refused; nothing was written |
//! | 2 | not solved: the run finished and wrote its results, but a status is not `solved` |
//! | 3 | I/O or resource error: a file could not be read or written, the output directory is in use, or the scene would need more elements or memory than allowed |

use std::process::ExitCode;

use signorini_core::mesh::MeshError;
use signorini_core::preflight::PreflightError;

use crate::output::OutputError;
use crate::run::RunError;
use crate::sweep::SweepError;
use signorini_core::model::ModelError;

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

/// The exit code an error deserves: [`Exit::Resource`] when anything in its chain is an I/O or
/// output error or a resource refusal, else [`Exit::Input`].
pub fn classify(error: &anyhow::Error) -> Exit {
    for cause in error.chain() {
        // A scene that cannot be read is the user's input (a wrong path), not the machine's.
        if cause.is::<signorini_core::scene::SceneError>()
            || matches!(cause.downcast_ref::<RunError>(), Some(RunError::Scene(_)))
            || cause.is::<crate::suite::SuiteError>()
            || cause.is::<crate::suite::baseline::BaselineError>()
        {
            return Exit::Input;
        }
        if cause.is::<std::io::Error>()
            || cause.is::<OutputError>()
            || cause.is::<Resource>()
            || cause.is::<PreflightError>()
            || matches!(
                cause.downcast_ref::<signorini_core::qp::QpError>(),
                Some(signorini_core::qp::QpError::TooLarge { .. })
            )
            || matches!(
                cause.downcast_ref::<signorini_core::solve::SolveError>(),
                Some(signorini_core::solve::SolveError::Qp(
                    signorini_core::qp::QpError::TooLarge { .. }
                ))
            )
            || matches!(
                cause.downcast_ref::<MeshError>(),
                Some(MeshError::TooManyElements { .. })
            )
            || cause.downcast_ref::<RunError>().is_some_and(run_resource)
            || matches!(
                cause.downcast_ref::<SweepError>(),
                Some(SweepError::Output(_))
            )
            || matches!(
                cause.downcast_ref::<SweepError>(),
                Some(SweepError::Run(e)) if run_resource(e)
            )
            || matches!(
                cause.downcast_ref::<crate::sweep::merge::MergeError>(),
                Some(crate::sweep::merge::MergeError::Output(_))
            )
        {
            return Exit::Resource;
        }
    }
    Exit::Input
}

/// `transparent` errors forward `source()` past their inner error, so the variants that are
/// resource errors themselves are recognised by name.
fn run_resource(e: &RunError) -> bool {
    match e {
        RunError::Output(_) | RunError::Preflight(_) => true,
        // A backend's memory refusal (a KKT factor, a dense H) is the machine's limit too.
        RunError::Solve(signorini_core::solve::SolveError::Qp(
            signorini_core::qp::QpError::TooLarge { .. },
        )) => true,
        RunError::Model(ModelError::Mesh { source, .. }) => {
            matches!(source, MeshError::TooManyElements { .. })
        }
        _ => false,
    }
}

/// An error that is about the machine's resources rather than the input (exit code 3).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Resource(pub String);

#[cfg(test)]
mod tests {
    use super::*;

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
}
