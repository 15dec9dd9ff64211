//! Every array of a scene file has an exact length; a wrong one is refused naming the section and
//! the key (before this was enforced, serde/toml truncated over-long fixed arrays silently).

mod common;

use signorini_core::scene::{Scene, SceneError};

const BASE: &str = r#"
title = "two blocks"
[model]
plane = "strain"

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
value = [0, 0]

[[dirichlet]]
body = "lower"
region = [3, 3, 0, 1]

[[neumann]]
body = "upper"
region = [1, 2, 2, 2]
traction = [0, -1e-4]

[[neumann]]
body = "lower"
region = [1, 3, 0, 0]
points = [[1, 0], [3, 0], [3, 1]]
tx = [0, 0, 0]
ty = [1e-5, 0, 0]

[[contact]]
bodies = ["upper", "lower"]
region = [1, 2, 0.99, 1.01]

[[probe]]
name = "corner"
body = "upper"
point = [2, 2]
"#;

fn with(replace: &str, by: &str) -> String {
    common::replaced(BASE, replace, by)
}

/// The scene must be refused with an `Invalid` error whose section contains `section`, whose key
/// is `key` and whose reason contains `reason`.
fn refused(text: &str, section: &str, key: &str, reason: &str) {
    let (s, k, r) = common::invalid(text);
    assert!(
        s.contains(section) && k == key && r.contains(reason),
        "expected {section} / {key} / {reason}, got {s} / {k} / {r}"
    );
}

#[test]
fn base_scene_is_valid() {
    let s = Scene::from_toml(BASE).unwrap();
    assert_eq!(s.bodies.len(), 2);
    assert_eq!(s.probes[0].point, [2.0, 2.0]);
}

#[test]
fn over_long_polygon_vertex() {
    let text = with(
        "[[0, 1], [2, 1], [2, 2], [0, 2]]",
        "[[0, 1], [2, 1], [2, 2, 7], [0, 2]]",
    );
    refused(
        &text,
        "body \"upper\"",
        "polygon",
        "vertex 3 has 3 numbers, needs 2",
    );
    // The exact message of the issue.
    let msg = Scene::from_toml(&text).unwrap_err().to_string();
    assert_eq!(
        msg,
        "body \"upper\": `polygon` vertex 3 has 3 numbers, needs 2"
    );
}

#[test]
fn short_polygon_vertex() {
    let text = with(
        "[[0, 1], [2, 1], [2, 2], [0, 2]]",
        "[[0, 1], [2], [2, 2], [0, 2]]",
    );
    refused(
        &text,
        "body \"upper\"",
        "polygon",
        "vertex 2 has 1 number, needs 2",
    );
}

#[test]
fn over_long_and_short_regions() {
    refused(
        &with("region = [0, 0, 1, 2]", "region = [0, 0, 1, 2, 9]"),
        "dirichlet #1",
        "region",
        "has 5 numbers, needs 4",
    );
    refused(
        &with("region = [3, 3, 0, 1]", "region = [3, 3, 0]"),
        "dirichlet #2",
        "region",
        "has 3 numbers, needs 4",
    );
    refused(
        &with("region = [1, 2, 2, 2]", "region = [1, 2, 2, 2, 2]"),
        "neumann #1",
        "region",
        "has 5 numbers, needs 4",
    );
    refused(
        &with(
            "region = [1, 2, 0.99, 1.01]",
            "region = [1, 2, 0.99, 1.01, 5]",
        ),
        "contact #1",
        "region",
        "has 5 numbers, needs 4",
    );
}

#[test]
fn three_bodies_in_a_contact_pair() {
    let text = format!(
        "{}\n[[body]]\nname = \"third\"\npolygon = [[5, 0], [6, 0], [6, 1]]\nhmax = 0.2\n\
         young = 1.0\npoisson = 0.3\n[[dirichlet]]\nbody = \"third\"\nregion = [5, 6, 0, 0]\n",
        with(
            "bodies = [\"upper\", \"lower\"]",
            "bodies = [\"upper\", \"lower\", \"third\"]"
        )
    );
    refused(&text, "contact #1", "bodies", "names 3 bodies, needs 2");
    refused(
        &with("bodies = [\"upper\", \"lower\"]", "bodies = [\"upper\"]"),
        "contact #1",
        "bodies",
        "names 1 body, needs 2",
    );
}

#[test]
fn dirichlet_value_traction_and_gravity() {
    refused(
        &with("value = [0, 0]", "value = [0, 0, 0]"),
        "dirichlet #1",
        "value",
        "has 3 numbers, needs 2",
    );
    refused(
        &with("traction = [0, -1e-4]", "traction = [0, -1e-4, 3]"),
        "neumann #1",
        "traction",
        "has 3 numbers, needs 2",
    );
    refused(
        &with("traction = [0, -1e-4]", "traction = [0]"),
        "neumann #1",
        "traction",
        "has 1 number, needs 2",
    );
    refused(
        &with(
            "plane = \"strain\"",
            "plane = \"strain\"\ngravity = [0, -9.81, 0]",
        ),
        "[model]",
        "gravity",
        "has 3 numbers, needs 2",
    );
}

#[test]
fn linear_traction_arrays() {
    refused(
        &with(
            "points = [[1, 0], [3, 0], [3, 1]]",
            "points = [[1, 0], [3, 0], [3, 1], [1, 1]]",
        ),
        "neumann #2",
        "points",
        "has 4 points, needs 3",
    );
    refused(
        &with(
            "points = [[1, 0], [3, 0], [3, 1]]",
            "points = [[1, 0], [3, 0, 1], [3, 1]]",
        ),
        "neumann #2",
        "points",
        "point 2 has 3 numbers, needs 2",
    );
    refused(
        &with("tx = [0, 0, 0]", "tx = [0, 0, 0, 0]"),
        "neumann #2",
        "tx",
        "has 4 numbers, needs 3",
    );
    refused(
        &with("ty = [1e-5, 0, 0]", "ty = [1e-5, 0]"),
        "neumann #2",
        "ty",
        "has 2 numbers, needs 3",
    );
}

#[test]
fn probe_point() {
    refused(
        &with("point = [2, 2]", "point = [2, 2, 2]"),
        "probe #1",
        "point",
        "has 3 numbers, needs 2",
    );
}

#[test]
fn unknown_keys_are_still_refused() {
    let err = Scene::from_toml(&with("point = [2, 2]", "point = [2, 2]\npiont = 1")).unwrap_err();
    assert!(matches!(err, SceneError::Syntax(_)), "{err}");
}
