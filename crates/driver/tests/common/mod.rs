//! What the driver's integration tests share: running the built `signorini` binary.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the `signorini` binary built for these tests with `args` in `cwd`.
pub fn signorini(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_signorini"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run signorini")
}

/// `path` relative to the repository's root.
pub fn repo(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

/// The JSON file at `path`, parsed.
pub fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("read")).expect("JSON")
}

/// Two unit blocks, the upper one pushed down onto the lower, clamped one; `young`, the traction
/// and the upper block's prescribed x-displacement are the knobs.
pub fn blocks(young: &str, traction: &str, value: &str) -> String {
    format!(
        r#"title = "blocks"
[[body]]
name = "upper"
polygon = [[0, 1], [1, 1], [1, 2], [0, 2]]
hmax = 0.5
young = {young}
poisson = 0.3
[[body]]
name = "lower"
polygon = [[0, 0], [1, 0], [1, 1], [0, 1]]
hmax = 0.5
young = {young}
poisson = 0.3
[[dirichlet]]
body = "lower"
region = [0, 1, 0, 0]
[[dirichlet]]
body = "upper"
region = [0, 0, 1, 2]
components = ["x"]
value = [{value}, 0]
[[neumann]]
body = "upper"
region = [0, 1, 2, 2]
traction = [0, {traction}]
[[contact]]
bodies = ["upper", "lower"]
"#
    )
}
