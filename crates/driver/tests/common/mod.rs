//! What the driver's integration tests share: running the built `signorini` binary.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Runs the `signorini` binary built for these tests with `args` in `cwd`.
pub fn signorini(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run signorini")
}
