//! Checks that used to fail only after meshing (or never), now refused by scene validation with
//! the section and the key named: control characters in names, contact boxes that miss a body,
//! bodies that nothing holds, and elastic constants or body forces that overflow.

use common::invalid;
use signorini_core::mesh::MeshLimits;
use signorini_core::model;
use signorini_core::scene::{Scene, MAX_COEFFICIENT};

mod common;

use common::TWO_BLOCKS;

/// The two blocks at hmax 0.25 with a probe at the upper block's corner.
fn base() -> String {
    let probe = "\n[[probe]]\nname = \"corner\"\nbody = \"upper\"\npoint = [2, 2]\n";
    format!(
        "{}{probe}",
        TWO_BLOCKS.replace("hmax = 0.2\n", "hmax = 0.25\n")
    )
}

fn with(replace: &str, by: &str) -> String {
    common::replaced(&base(), replace, by)
}

/// Meshes and assembles a valid scene the way `solve` does (up to the QP).
fn assembles(scene: &Scene) -> Result<(), String> {
    let meshes = model::mesh_scene(scene, &MeshLimits::default()).map_err(|e| e.to_string())?;
    model::assemble(scene, meshes)
        .map(|_| ())
        .map_err(|e| e.to_string())
}

#[test]
fn base_scene_is_valid_and_assembles() {
    let s = Scene::from_toml(&base()).unwrap();
    assembles(&s).unwrap();
}

#[test]
fn control_characters_in_names_and_title() {
    // TOML escapes put any control character into a string.
    let (s, k, r) = invalid(&with("name = \"upper\"", "name = \"up\\u0007per\""));
    assert!(
        s.starts_with("body") && k == "name" && r.contains("U+0007"),
        "{s} {k} {r}"
    );
    // The section label escapes the name instead of printing the raw character.
    assert!(s.contains("\\u{7}") && !s.contains('\u{7}'), "{s}");
    let (s, k, r) = invalid(&with("name = \"corner\"", "name = \"cor\\nner\""));
    assert!(
        s.starts_with("probe #1") && k == "name" && r.contains("U+000A"),
        "{s} {k} {r}"
    );
    let (s, k, r) = invalid(&with(
        "title = \"two blocks\"",
        "title = \"two\\u001bblocks\"",
    ));
    assert!(
        s == "scene" && k == "title" && r.contains("U+001B"),
        "{s} {k} {r}"
    );
    // C1 controls and DEL too.
    let (_, k, r) = invalid(&with("name = \"lower\"", "name = \"low\\u0085er\""));
    assert!(k == "name" && r.contains("U+0085"), "{r}");
    let (_, k, _) = invalid(&with("name = \"lower\"", "name = \"low\\u007Fer\""));
    assert_eq!(k, "name");
    // Printable Unicode, quotes and spaces stay legal; the empty-name check stays.
    let ok = with("name = \"lower\"", "name = \"unten \\\"ü\\\" 下\"")
        .replace("body = \"lower\"", "body = \"unten \\\"ü\\\" 下\"")
        .replace("\"upper\", \"lower\"", "\"upper\", \"unten \\\"ü\\\" 下\"");
    let scene = Scene::from_toml(&ok).unwrap();
    assert_eq!(scene.bodies[1].name, "unten \"ü\" 下");
    let (_, k, r) = invalid(&with("name = \"lower\"", "name = \"  \""));
    assert!(k == "name" && r.contains("empty"), "{r}");
}

#[test]
fn contact_box_missing_one_body_is_refused_before_meshing() {
    // The box [1, 2] × [1.5, 1.6] meets the upper body's right edge only; it holds no boundary
    // of "lower" (which ends at y = 1).  Before, this failed after meshing (EmptyRegion).
    let text = with("region = [1, 2, 0.99, 1.01]", "region = [1, 2, 1.5, 1.6]");
    let (s, k, r) = invalid(&text);
    assert!(
        s.starts_with("contact #1") && k == "region" && r.contains("no boundary"),
        "{s} {k} {r}"
    );
    // A box touching the upper body's top edge only: misses "lower".
    let text = with("region = [1, 2, 0.99, 1.01]", "region = [1, 2, 1.99, 2.01]");
    let (s, k, r) = invalid(&text);
    assert!(
        s.starts_with("contact #1") && k == "region" && r.contains("\"lower\""),
        "{s} {k} {r}"
    );
}

#[test]
fn contact_box_meeting_both_boundaries_meshes_and_assembles() {
    // A box meeting both bodies' boundaries passes validation and the contact search finds
    // candidates in it (what the late EmptyRegion check demanded).
    for region in [
        "[1, 2, 0.99, 1.01]",
        "[1.4, 1.6, 0.9, 1.1]",
        "[0.5, 2.5, 0.5, 1.5]",
    ] {
        let text = with("region = [1, 2, 0.99, 1.01]", &format!("region = {region}"));
        let scene = Scene::from_toml(&text).unwrap();
        assembles(&scene).unwrap_or_else(|e| panic!("{region}: {e}"));
    }
}

#[test]
fn body_held_by_nothing_is_refused() {
    // No contact pair and no support for "lower": before, `check` passed and assembly failed.
    let text = with(
        "[[contact]]\nbodies = [\"upper\", \"lower\"]\nregion = [1, 2, 0.99, 1.01]",
        "",
    )
    .replace("[[dirichlet]]\nbody = \"lower\"\nregion = [3, 3, 0, 1]", "");
    let (s, k, r) = invalid(&text);
    assert!(
        s == "body \"lower\"" && k == "dirichlet" && r.contains("nothing holds"),
        "{s} {k} {r}"
    );
    // The same body in a contact pair is held (the model regularises it through the contact).
    let held = base().replace("[[dirichlet]]\nbody = \"lower\"\nregion = [3, 3, 0, 1]", "");
    Scene::from_toml(&held).unwrap();
}

#[test]
fn supports_that_leave_rigid_modes_free_are_refused_like_assembly_does() {
    let no_contact = with(
        "[[contact]]\nbodies = [\"upper\", \"lower\"]\nregion = [1, 2, 0.99, 1.01]",
        "",
    );
    // One corner point: the rotation about it is free (1 mode).
    let point = no_contact.replace("region = [3, 3, 0, 1]", "region = [3, 3, 0, 0]");
    let (s, k, r) = invalid(&point);
    assert!(
        s == "body \"lower\"" && k == "dirichlet" && r.contains("1 rigid-body mode"),
        "{s} {k} {r}"
    );
    // A roller in x along a vertical edge: y translation free.
    let roller = no_contact.replace(
        "region = [3, 3, 0, 1]",
        "region = [3, 3, 0, 1]\ncomponents = [\"x\"]",
    );
    let (_, k, r) = invalid(&roller);
    assert!(k == "dirichlet" && r.contains("1 rigid-body mode"), "{r}");
    // The model's own check (independent: it works on the mesh nodes) agrees: the same supports
    // put into a valid scene behind validation's back make assembly refuse the body.
    let mut scene = Scene::from_toml(&no_contact).unwrap();
    scene.dirichlet[1].region = [3.0, 3.0, 0.0, 0.0];
    let err = assembles(&scene).unwrap_err();
    assert!(
        err.contains("\"lower\" is not held") && err.contains("1 rigid"),
        "{err}"
    );
    let mut scene = Scene::from_toml(&no_contact).unwrap();
    scene.dirichlet[1].components = [true, false];
    let err = assembles(&scene).unwrap_err();
    assert!(
        err.contains("\"lower\" is not held") && err.contains("1 rigid"),
        "{err}"
    );
    // Two supported components on an edge: held, and assembly agrees.
    let edge = no_contact.replace(
        "region = [3, 3, 0, 1]",
        "region = [3, 3, 0, 1]\ncomponents = [\"x\", \"y\"]",
    );
    let scene = Scene::from_toml(&edge).unwrap();
    assembles(&scene).unwrap();
    // x on a vertical edge plus y at one point: held.
    let mixed = format!(
        "{}\n[[dirichlet]]\nbody = \"lower\"\nregion = [1, 1, 0, 0]\ncomponents = [\"y\"]\n",
        roller
    );
    let scene = Scene::from_toml(&mixed).unwrap();
    assembles(&scene).unwrap();
}

#[test]
fn overflowing_young_modulus_is_refused() {
    // E = 1e308 passed before and the element stiffness became inf.
    let (s, k, r) = invalid(&with("young = 0.0012", "young = 1e308"));
    assert!(
        s == "body \"lower\"" && k == "young" && r.contains("overflow"),
        "{s} {k} {r}"
    );
    // ν close to 1/2 amplifies λ = Eν/((1+ν)(1−2ν)) by 1/(1−2ν) = 5e15.
    let (_, k, _) = invalid(&with(
        "young = 0.0012\npoisson = 0.34",
        "young = 1e290\npoisson = 0.4999999999999999",
    ));
    assert_eq!(k, "young");
    // Plane stress: thickness multiplies.
    let (_, k, r) = invalid(&format!(
        "{}\n[model]\nplane = \"stress\"\nthickness = 1e300\n",
        with("young = 0.0012", "young = 1.0")
    ));
    assert!(k == "young" && r.contains("thickness"), "{r}");
    // Just inside the bound: accepted (the bound is MAX_COEFFICIENT on (λ+2μ)·t).
    // Plane strain, ν = 0: λ + 2μ = E.
    let e = MAX_COEFFICIENT * 0.5;
    let text = with(
        "young = 0.0012\npoisson = 0.34",
        &format!("young = {e:e}\npoisson = 0.0"),
    );
    Scene::from_toml(&text).unwrap();
}

#[test]
fn tiny_material_values_are_legitimate() {
    // The program nondimensionalises: E = 1e-200 must not be refused, and assembles.
    let text = with("young = 0.0012", "young = 1e-200").replace("young = 0.0021", "young = 1e-200");
    let scene = Scene::from_toml(&text).unwrap();
    assembles(&scene).unwrap();
}

#[test]
fn underflowing_material_values_are_refused() {
    // E = 2.2e-308 (f64::MIN_POSITIVE) gave element stiffnesses of zero: `check` accepted the
    // scene and the Cholesky factorisation of `solve` then failed (found by the fuzz harness).
    let (_, k, r) = invalid(&with("young = 0.0012", "young = 2.2250738585072014e-308"));
    assert!(k == "young" && r.contains("underflow"), "{k}: {r}");
    // Plane stress: E = 1e-200 is fine alone, but with thickness 1e-200 the product underflows.
    let (_, k, _) = invalid(&format!(
        "{}\n[model]\nplane = \"stress\"\nthickness = 1e-200\n",
        with("young = 0.0012", "young = 1e-200")
    ));
    assert_eq!(k, "young");
}

#[test]
fn overflowing_body_force_is_refused() {
    let gravity = |rho: &str| {
        format!(
            "{}\n[model]\ngravity = [0, -9.81]\n",
            base()
                .replace(
                    "poisson = 0.3\n",
                    &format!("poisson = 0.3\ndensity = {rho}\n")
                )
                .replace("poisson = 0.34\n", "poisson = 0.34\ndensity = 1.0\n")
        )
    };
    Scene::from_toml(&gravity("7800")).unwrap();
    let (s, k, r) = invalid(&gravity("1e308"));
    assert!(
        s == "body \"upper\"" && k == "density" && r.contains("overflow"),
        "{s} {k} {r}"
    );
}

#[test]
fn polygons_whose_area_overflows_are_refused() {
    // Coordinates of 1e200 make x·y overflow: the area was NaN and passed the zero-area test.
    let (s, k, r) = invalid(&with(
        "[[1, 0], [3, 0], [3, 1], [1, 1]]",
        "[[1e200, 0], [3e200, 0], [3e200, 1e200], [1e200, 1e200]]",
    ));
    assert!(
        s == "body \"lower\"" && k == "polygon" && r.contains("overflow"),
        "{s} {k} {r}"
    );
}

#[test]
fn a_contact_box_meeting_the_boundary_only_near_a_corner_still_gets_a_node() {
    // Experiment 2b at hmax 0.25 with a contact box that crosses the interface 0.02 from the
    // corner (1, 1) and holds no vertex: validation accepts it (the box meets both boundaries),
    // so assembly must give it a row. Its crossings used to be dropped as "near a corner"
    // (to avoid slivers), leaving no node in the box and failing after meshing.
    let text = std::fs::read_to_string(
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/seed/exp2b.toml"),
    )
    .expect("fixture");
    let text = text.replace("hmax = 0.2", "hmax = 0.25").replace(
        "region = [1, 2, 0.99, 1.01]",
        "region = [1.02, 1.03, 0.99, 1.01]",
    );
    assert!(
        text.contains("[1.02, 1.03, 0.99, 1.01]"),
        "the fixture's box changed"
    );
    let scene = signorini_core::scene::Scene::from_toml(&text).expect("valid scene");
    let meshes = signorini_core::model::mesh_scene(&scene, &Default::default()).expect("mesh");
    let model = signorini_core::model::assemble(&scene, meshes).expect("assembles");
    assert!(model.model.rows() >= 1);
}

#[test]
fn conflicting_supports_are_refused_before_meshing() {
    // A second support on the lower body's corner (3, 0) with a different x value: before, the
    // FEM stage refused it after meshing (ConflictingDirichlet).
    let text = format!(
        "{}\n[[dirichlet]]\nbody = \"lower\"\nregion = [2, 3, 0, 0]\nvalue = [0.1, 0]\n",
        base()
    );
    let (s, k, r) = invalid(&text);
    assert!(
        s.starts_with("dirichlet #3")
            && k == "value"
            && r.contains("dirichlet #2")
            && r.contains("(3, 0)"),
        "{s} {k} {r}"
    );
    // The model agrees (independent: it compares the values at the mesh nodes).
    let mut scene = Scene::from_toml(&text.replace("value = [0.1, 0]", "value = [0, 0]")).unwrap();
    scene.dirichlet[2].value = [0.1, 0.0];
    let err = assembles(&scene).unwrap_err();
    assert!(err.contains("prescribe different x"), "{err}");
    // Equal values, disjoint boxes, or different components are fine.
    Scene::from_toml(&text.replace("value = [0.1, 0]", "value = [0, 0]")).unwrap();
    Scene::from_toml(&text.replace("region = [2, 3, 0, 0]", "region = [1, 2, 0, 0]")).unwrap();
    let roller = text.replace("value = [0.1, 0]", "value = [0.1, 0]\ncomponents = [\"y\"]");
    Scene::from_toml(&roller).unwrap();
}

mod agreement {
    //! Random supports and contact boxes on the two blocks: what validation accepts, the model
    //! meshes and assembles (no late EmptyRegion, Unsupported or ConflictingDirichlet).

    use super::*;
    use proptest::prelude::*;

    /// Box coordinates on a grid of quarter units, so that boxes hit edges, corners and nothing.
    fn coordinate() -> impl Strategy<Value = f64> {
        (-2i32..=14).prop_map(|k| k as f64 * 0.25)
    }

    fn region() -> impl Strategy<Value = [f64; 4]> {
        (coordinate(), coordinate(), coordinate(), coordinate())
            .prop_map(|(a, b, c, d)| [a.min(b), a.max(b), c.min(d), c.max(d)])
    }

    #[derive(Debug, Clone)]
    struct Support {
        body: &'static str,
        region: [f64; 4],
        components: &'static str,
        value: f64,
    }

    fn support() -> impl Strategy<Value = Support> {
        (
            prop_oneof![Just("upper"), Just("lower")],
            region(),
            prop_oneof![Just("[\"x\", \"y\"]"), Just("[\"x\"]"), Just("[\"y\"]")],
            prop_oneof![Just(0.0), Just(0.01)],
        )
            .prop_map(|(body, region, components, value)| Support {
                body,
                region,
                components,
                value,
            })
    }

    fn scene(supports: &[Support], contact: Option<Option<[f64; 4]>>) -> String {
        let mut text = String::from(
            "[[body]]\nname = \"upper\"\npolygon = [[0, 1], [2, 1], [2, 2], [0, 2]]\nhmax = 0.25\n\
             young = 1.0\npoisson = 0.3\n\
             [[body]]\nname = \"lower\"\npolygon = [[1, 0], [3, 0], [3, 1], [1, 1]]\nhmax = 0.25\n\
             young = 1.0\npoisson = 0.3\n",
        );
        for s in supports {
            text += &format!(
                "[[dirichlet]]\nbody = \"{}\"\nregion = {:?}\ncomponents = {}\nvalue = [{}, 0]\n",
                s.body, s.region, s.components, s.value
            );
        }
        if let Some(region) = contact {
            text += "[[contact]]\nbodies = [\"upper\", \"lower\"]\n";
            if let Some(r) = region {
                text += &format!("region = {r:?}\n");
            }
        }
        text
    }

    proptest! {
        // A fixed draw: the suite must not pass or fail by chance.
        #![proptest_config(ProptestConfig {
            cases: 600,
            rng_seed: proptest::test_runner::RngSeed::Fixed(20_261_123),
            ..ProptestConfig::default()
        })]

        #[test]
        fn accepted_scenes_assemble(
            supports in prop::collection::vec(support(), 0..4),
            contact in prop::option::of(prop::option::of(region())),
        ) {
            let text = scene(&supports, contact);
            // About one scene in six is valid (the rest are refused, mostly for boxes that miss).
            let Ok(scene) = Scene::from_toml(&text) else {
                return Ok(());
            };
            if let Err(e) = assembles(&scene) {
                // Whether a body held only by contact gets a row acting on it is known only once
                // the contact rows exist: that refusal (ModelError::NotHeld) belongs to assembly,
                // which `check` runs too, so check and solve still agree.
                prop_assume!(!e.contains("is held only by contact"));
                prop_assert!(false, "validation accepted but the model refused: {e}\n{text}");
            }
        }
    }
}
