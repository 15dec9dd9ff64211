//! Every kind of bad scene is refused with a typed error naming the section and key.

use signorini_core::scene::{Scene, SceneError};

mod common;

use common::{invalid, TWO_BLOCKS as BASE};

fn with(replace: &str, by: &str) -> String {
    common::replaced(BASE, replace, by)
}

#[test]
fn base_scene_is_valid() {
    let s = Scene::from_toml(BASE).unwrap();
    assert_eq!(s.bodies.len(), 2);
    assert_eq!(s.contacts[0].bodies, [0, 1]);
    assert_eq!(s.dirichlet[0].components, [true, true]);
    assert!((s.size() - 13f64.sqrt()).abs() < 1e-12);
}

#[test]
fn unknown_key_is_a_syntax_error_with_position() {
    let err = Scene::from_toml(&with(
        "hmax = 0.2\nyoung = 0.0021",
        "hmax = 0.2\nyoung = 0.0021\nyuong = 1",
    ))
    .unwrap_err();
    let msg = err.to_string();
    assert!(matches!(err, SceneError::Syntax(_)));
    assert!(msg.contains("yuong") && msg.contains("line"), "{msg}");
}

#[test]
fn malformed_toml_reports_line_and_column() {
    let err = Scene::from_toml("[[body]\nname = 1").unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains("line 1") && msg.contains("column"), "{msg}");
}

#[test]
fn unknown_and_duplicate_body_names() {
    let (s, k, r) = invalid(&with(
        "body = \"lower\"\nregion = [3",
        "body = \"lowr\"\nregion = [3",
    ));
    assert!(
        s.contains("dirichlet #2") && k == "body" && r.contains("lowr"),
        "{s} {k} {r}"
    );
    let (s, k, _) = invalid(&with("name = \"lower\"", "name = \"upper\""));
    assert!(s.contains("upper") && k == "name");
}

#[test]
fn material_and_mesh_size_ranges() {
    for (from, to, key) in [
        ("young = 0.0012", "young = 0.0", "young"),
        ("young = 0.0012", "young = -3.0", "young"),
        ("young = 0.0012", "young = inf", "young"),
        ("poisson = 0.34", "poisson = 0.5", "poisson"),
        ("poisson = 0.34", "poisson = -1.0", "poisson"),
        ("poisson = 0.34", "poisson = nan", "poisson"),
        (
            "hmax = 0.2\nyoung = 0.0012",
            "hmax = 0.0\nyoung = 0.0012",
            "hmax",
        ),
    ] {
        let (s, k, r) = invalid(&with(from, to));
        assert_eq!(k, key, "{s}: {r}");
        assert!(s.contains("lower"), "{s}");
    }
}

#[test]
fn bad_polygons() {
    let (_, k, r) = invalid(&with(
        "[[1, 0], [3, 0], [3, 1], [1, 1]]",
        "[[1, 0], [3, 0]]",
    ));
    assert!(k == "polygon" && r.contains("3 vertices"));
    let (_, k, r) = invalid(&with(
        "[[1, 0], [3, 0], [3, 1], [1, 1]]",
        "[[1, 0], [2, 0], [3, 0]]",
    ));
    assert!(k == "polygon" && r.contains("zero area"), "{r}");
    let (_, k, r) = invalid(&with(
        "[[1, 0], [3, 0], [3, 1], [1, 1]]",
        "[[1, 0], [3, 0], [3, 1], [2, -1]]",
    ));
    assert!(k == "polygon" && r.contains("not simple"), "{r}");
}

#[test]
fn clockwise_polygon_is_reoriented() {
    let s = Scene::from_toml(&with(
        "[[1, 0], [3, 0], [3, 1], [1, 1]]",
        "[[1, 1], [3, 1], [3, 0], [1, 0]]",
    ))
    .unwrap();
    assert!(signorini_core::geometry::signed_area(&s.bodies[1].polygon) > 0.0);
}

#[test]
fn collinear_traction_points() {
    let text = with(
        "traction = [0, -1e-4]",
        "points = [[1, 2], [1.5, 2], [2, 2]]\ntx = [0, 0, 0]\nty = [-1e-4, 0, 0]",
    );
    let (s, k, _) = invalid(&text);
    assert!(s.contains("neumann #1") && k == "points");
}

#[test]
fn linear_traction_is_interpolated() {
    let text = with(
        "traction = [0, -1e-4]",
        "points = [[1, 2], [2, 2], [2, 1]]\ntx = [5e-5, 5e-5, 5e-5]\nty = [-1e-4, 0, 0]",
    );
    let s = Scene::from_toml(&text).unwrap();
    let t = s.neumann[0].traction;
    let mid = t.at([1.5, 2.0]);
    assert!((mid[0] - 5e-5).abs() < 1e-18 && (mid[1] + 5e-5).abs() < 1e-18);
}

#[test]
fn regions_that_miss_the_body() {
    let (s, k, r) = invalid(&with("region = [0, 0, 1, 2]", "region = [5, 5, 1, 2]"));
    assert!(s.contains("dirichlet #1") && k == "region" && r.contains("no boundary node"));
    let (s, k, _) = invalid(&with(
        "region = [1, 2, 2, 2]",
        "region = [0.5, 1.5, 1.5, 1.6]",
    ));
    assert!(s.contains("neumann #1") && k == "region");
    // A box that touches the boundary in one point loads no edge.
    let (_, k, r) = invalid(&with("region = [1, 2, 2, 2]", "region = [2, 3, 2, 3]"));
    assert!(k == "region" && r.contains("no boundary edge"), "{r}");
    let (_, k, _) = invalid(&with("region = [1, 2, 2, 2]", "region = [2, 1, 2, 2]"));
    assert_eq!(k, "region");
}

#[test]
fn q1_needs_a_rectangle() {
    let text = with(
        "polygon = [[1, 0], [3, 0], [3, 1], [1, 1]]\nhmax = 0.2",
        "polygon = [[1, 0], [3, 0], [3, 1], [1, 1.5]]\nhmax = 0.2\nelement = \"q1\"",
    );
    let (s, k, _) = invalid(&text);
    assert!(s.contains("lower") && k == "element");
    let ok = with(
        "polygon = [[1, 0], [3, 0], [3, 1], [1, 1]]\nhmax = 0.2",
        "polygon = [[1, 0], [3, 0], [3, 1], [1, 1]]\nhmax = 0.2\nelement = \"q1\"",
    );
    assert!(Scene::from_toml(&ok).is_ok());
}

#[test]
fn contact_pair_naming_one_body_twice() {
    let (s, k, _) = invalid(&with(
        "bodies = [\"upper\", \"lower\"]",
        "bodies = [\"upper\", \"upper\"]",
    ));
    assert!(s.contains("contact #1") && k == "bodies");
    let (_, k, _) = invalid(&with(
        "region = [1, 2, 0.99, 1.01]",
        "region = [1, 2, 0.99, 1.01]\nslave = \"nobody\"",
    ));
    // The key at fault is `slave` (it named the unknown body).
    assert_eq!(k, "slave");
}

#[test]
fn thickness_density_and_probe_checks() {
    let (_, k, _) = invalid(&format!("{BASE}\n[model]\nthickness = 2.0\n"));
    assert_eq!(k, "thickness");
    assert!(Scene::from_toml(&format!(
        "{BASE}\n[model]\nplane = \"stress\"\nthickness = 2.0\n"
    ))
    .is_ok());
    let (s, k, _) = invalid(&format!("{BASE}\n[model]\ngravity = [0, -9.81]\n"));
    assert!(s.contains("upper") && k == "density");
    let (s, k, _) = invalid(&format!(
        "{BASE}\n[[probe]]\nname = \"p\"\nbody = \"upper\"\npoint = [5, 5]\n"
    ));
    assert!(s.contains("probe") && k == "point");
}

#[test]
fn components_and_values() {
    let text = with(
        "region = [3, 3, 0, 1]",
        "region = [3, 3, 0, 1]\nvalue = [-0.08, 0]\ncomponents = [\"x\"]",
    );
    let s = Scene::from_toml(&text).unwrap();
    assert_eq!(s.dirichlet[1].components, [true, false]);
    assert_eq!(s.dirichlet[1].value, [-0.08, 0.0]);
    let (_, k, _) = invalid(&with(
        "region = [3, 3, 0, 1]",
        "region = [3, 3, 0, 1]\ncomponents = []",
    ));
    assert_eq!(k, "components");
    let err = Scene::from_toml(&with(
        "region = [3, 3, 0, 1]",
        "region = [3, 3, 0, 1]\ncomponents = [\"z\"]",
    ))
    .unwrap_err();
    assert!(matches!(err, SceneError::Syntax(_)));
}

#[test]
fn no_bodies() {
    let (_, k, _) = invalid("title = \"empty\"");
    assert_eq!(k, "body");
}
