//! Helpers shared by the scene tests: the two-block scene of the seed's Experiment 2b and the
//! unpacking of a refusal.
#![allow(dead_code)]

use signorini_core::scene::{Scene, SceneError};

/// Two blocks, the upper one pressed onto the lower one (Experiment 2b's geometry, hmax 0.2).
pub const TWO_BLOCKS: &str = r#"
title = "two blocks"
[[body]]
name = "upper"
polygon = [[0, 1], [2, 1], [2, 2], [0, 2]]
hmax = 0.2
young = 0.0021
poisson = 0.3

[[body]]
name = "lower"
polygon = [[1, 0], [3, 0], [3, 1], [1, 1]]
hmax = 0.2
young = 0.0012
poisson = 0.34

[[dirichlet]]
body = "upper"
region = [0, 0, 1, 2]

[[dirichlet]]
body = "lower"
region = [3, 3, 0, 1]

[[neumann]]
body = "upper"
region = [1, 2, 2, 2]
traction = [0, -1e-4]

[[contact]]
bodies = ["upper", "lower"]
region = [1, 2, 0.99, 1.01]
"#;

/// `base` with the first `replace` replaced by `by` (which must be there).
pub fn replaced(base: &str, replace: &str, by: &str) -> String {
    assert!(base.contains(replace), "{replace}");
    base.replacen(replace, by, 1)
}

/// The section, key and reason of a refusal; panics on anything else.
pub fn invalid(text: &str) -> (String, &'static str, String) {
    match Scene::from_toml(text) {
        Err(SceneError::Invalid {
            section,
            key,
            reason,
        }) => (section, key, reason),
        other => panic!("expected an Invalid error, got {other:?}"),
    }
}
