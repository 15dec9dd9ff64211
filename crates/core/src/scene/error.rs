//! The error of reading and validating a scene.

/// A scene that could not be read or is not valid.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("cannot read scene file {path}")]
    Read {
        /// The path given.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The TOML is malformed or has unknown or mistyped keys (the message carries line and column).
    #[error("scene is not valid TOML for signorini: {0}")]
    Syntax(String),
    /// A value is out of range or inconsistent.
    #[error("{section}: `{key}` {reason}")]
    Invalid {
        /// Where: e.g. `body "upper"` or `dirichlet #2 (body "lower")`.
        section: String,
        /// The offending key.
        key: &'static str,
        /// What is wrong, with the value.
        reason: String,
    },
}

impl SceneError {
    pub(crate) fn invalid(
        section: impl Into<String>,
        key: &'static str,
        reason: impl Into<String>,
    ) -> Self {
        SceneError::Invalid {
            section: section.into(),
            key,
            reason: reason.into(),
        }
    }
}
