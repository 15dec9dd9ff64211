//! Writing to the terminal: standard output with errors reported, standard error best-effort.

use std::io::Write;

use anyhow::{Context, Result};

/// Standard output with write errors turned into errors (a closed pipe or a full disk is a clean
/// failure with exit code 3, never a panic as `println!` would give).
pub(crate) struct Console(std::io::Stdout);

impl Console {
    pub(crate) fn new() -> Self {
        Console(std::io::stdout())
    }

    pub(crate) fn line(&mut self, text: impl std::fmt::Display) -> Result<()> {
        writeln!(self.0, "{text}").context("writing to standard output")
    }

    pub(crate) fn finish(mut self) -> Result<()> {
        self.0.flush().context("writing to standard output")
    }
}

/// Prints to standard error, ignoring failure: there is nowhere left to report it.
pub(crate) fn warn(text: impl std::fmt::Display) {
    let _ = writeln!(std::io::stderr(), "{text}");
}
