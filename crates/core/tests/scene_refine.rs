//! `[[body.refine]]` at the scene level: what validation refuses (each message names the table
//! and the key), what it accepts, and that the refined body really is meshed finer near the box.

#![allow(clippy::unwrap_used)] // tests may unwrap (helpers included)

mod common;

use common::{invalid, replaced, TWO_BLOCKS};
use signorini_core::mesh::MeshLimits;
use signorini_core::model::mesh_scene;
use signorini_core::scene::Scene;

/// TWO_BLOCKS with a refine table appended to the upper body (hmax 0.2).
fn with_refine(table: &str) -> String {
    replaced(
        TWO_BLOCKS,
        "young = 0.0021\npoisson = 0.3\n",
        &format!("young = 0.0021\npoisson = 0.3\n\n[[body.refine]]\n{table}\n"),
    )
}

#[test]
fn refine_hmax_not_below_the_body_hmax_is_refused() {
    for hmax in ["0.2", "0.3"] {
        let (section, key, reason) = invalid(&with_refine(&format!(
            "region = [1, 2, 0.9, 1.1]\nhmax = {hmax}"
        )));
        assert_eq!(key, "hmax");
        assert!(
            section.contains("upper") && section.contains("refine #1"),
            "{section}"
        );
        assert!(reason.contains("0.2"), "{reason}");
    }
    for hmax in ["0", "-0.1", "nan", "inf"] {
        let (section, key, _) = invalid(&with_refine(&format!(
            "region = [1, 2, 0.9, 1.1]\nhmax = {hmax}"
        )));
        assert_eq!(key, "hmax", "{hmax}");
        assert!(section.contains("refine #1"));
    }
}

#[test]
fn refine_box_outside_the_body_is_refused() {
    // The upper body is [0, 2] × [1, 2]; this box lies below it.
    let (section, key, reason) =
        invalid(&with_refine("region = [0.5, 1.5, 0.2, 0.5]\nhmax = 0.05"));
    assert_eq!(key, "region");
    assert!(
        section.contains("upper") && section.contains("refine #1"),
        "{section}"
    );
    assert!(reason.contains("outside"), "{reason}");
}

#[test]
fn refine_region_needs_four_ordered_numbers() {
    let (section, key, reason) = invalid(&with_refine("region = [1, 2, 1.5]\nhmax = 0.05"));
    assert_eq!(key, "region");
    assert!(section.contains("refine #1"), "{section}");
    assert!(reason.contains("needs 4"), "{reason}");
    let (_, key, _) = invalid(&with_refine("region = [2, 1, 1.5, 1.8]\nhmax = 0.05"));
    assert_eq!(key, "region");
}

#[test]
fn refine_box_meshes_the_body_finer_there_only() {
    // A box along the interface y = 1, x ∈ [1, 2]: the upper body's bottom edge there is split
    // into pieces ≤ 0.02, outside the box's influence the edges stay ≤ 0.2.
    let text = with_refine("region = [1, 2, 0.95, 1.05]\nhmax = 0.02");
    let scene = Scene::from_toml(&text).unwrap();
    assert_eq!(scene.bodies[0].refine.len(), 1);
    let meshes = mesh_scene(&scene, &MeshLimits::default()).unwrap();
    let upper = &meshes[0];
    let on_interface: Vec<f64> = upper
        .nodes
        .iter()
        .filter(|p| p[1] == 1.0 && (1.0..=2.0).contains(&p[0]))
        .map(|p| p[0])
        .collect();
    // 1 / 0.02 = 50 pieces at least on [1, 2].
    assert!(on_interface.len() >= 51, "{}", on_interface.len());
    // The lower body has no refine table: its mesh is the one without (hmax 0.2: 6 nodes on
    // [1, 2] as in the seed), so the interface is non-conforming, as with unequal hmax.
    let lower = &meshes[1];
    let lower_interface = lower
        .nodes
        .iter()
        .filter(|p| p[1] == 1.0 && (1.0..=2.0).contains(&p[0]))
        .count();
    assert_eq!(lower_interface, 6);
    // Far from the box (x < 0.3, y > 1.8): h = hmax, so edges there may reach 0.2 and the mesh
    // there is as coarse as the uniform one (no node closer than 0.05 to another).
    let far: Vec<[f64; 2]> = upper
        .nodes
        .iter()
        .copied()
        .filter(|p| p[0] < 0.3 && p[1] > 1.8)
        .collect();
    for (i, p) in far.iter().enumerate() {
        for q in &far[i + 1..] {
            assert!((p[0] - q[0]).hypot(p[1] - q[1]) > 0.05, "{p:?} {q:?}");
        }
    }
}

/// A refine box whose side passes just beside a corner (0.001 from x = 0) must not force a
/// sliver: that crossing is skipped (the corner is a node already), so the P1 mesh keeps the
/// 20° bound and the Q1 grid has no column narrower than half the region's size.
#[test]
fn refine_box_beside_a_corner_makes_no_sliver() {
    for element in ["p1", "q1"] {
        let text = replaced(
            &with_refine("region = [0.001, 0.5, 1.5, 2.0]\nhmax = 0.05"),
            "hmax = 0.2\n",
            &format!("hmax = 0.2\nelement = \"{element}\"\n"),
        );
        let scene = Scene::from_toml(&text).unwrap();
        let limits = MeshLimits::default();
        let upper = &mesh_scene(&scene, &limits).unwrap()[0];
        if element == "p1" {
            assert!(
                upper.min_angle_deg() >= limits.min_angle_deg - 1e-9,
                "{}",
                upper.min_angle_deg()
            );
        } else {
            let mut xs: Vec<f64> = upper.nodes.iter().map(|p| p[0]).collect();
            xs.sort_by(f64::total_cmp);
            xs.dedup();
            let narrowest = xs.windows(2).map(|w| w[1] - w[0]).fold(f64::MAX, f64::min);
            assert!(narrowest >= 0.025 * (1.0 - 1e-9), "{narrowest}");
        }
        // The fine zone is there: many nodes on the top edge within the box.
        let fine = upper
            .nodes
            .iter()
            .filter(|p| p[1] == 2.0 && p[0] <= 0.5)
            .count();
        assert!(fine >= 10, "{element}: {fine}");
    }
}

/// Two blocks sharing the edge y = 1, x ∈ [1, 2], both with the same refine box across the
/// interface (and one of its sides 0.01 from the lower block's corner (1, 1), so the sliver
/// rule applies to one body's vertex only): `mesh_scene` gives both the same interface nodes.
#[test]
fn equal_refine_boxes_keep_the_interface_conforming() {
    let table = "\n[[body.refine]]\nregion = [1.01, 1.6, 0.9, 1.1]\nhmax = 0.04\n";
    let mut text = replaced(
        TWO_BLOCKS,
        "poisson = 0.3\n",
        &format!("poisson = 0.3\n{table}"),
    );
    text = replaced(
        &text,
        "poisson = 0.34\n",
        &format!("poisson = 0.34\n{table}"),
    );
    for element in ["p1", "q1"] {
        let text = text.replace(
            "hmax = 0.2\n",
            &format!("hmax = 0.2\nelement = \"{element}\"\n"),
        );
        let scene = Scene::from_toml(&text).unwrap();
        assert!(scene.bodies.iter().all(|b| b.refine.len() == 1));
        let meshes = mesh_scene(&scene, &MeshLimits::default()).unwrap();
        let interface = |i: usize| {
            let mut x: Vec<f64> = meshes[i]
                .nodes
                .iter()
                .filter(|p| p[1] == 1.0 && (1.0..=2.0).contains(&p[0]))
                .map(|p| p[0])
                .collect();
            x.sort_by(f64::total_cmp);
            x
        };
        let (a, b) = (interface(0), interface(1));
        // 0.59 / 0.04 ≈ 15 pieces inside the box alone.
        assert!(a.len() > 18, "{element}: {}", a.len());
        assert_eq!(a, b, "{element}");
        // The crossing 0.01 from the corner (1, 1) is not a node; the other one (1.6) is.
        assert!(!a.contains(&1.01) && a.contains(&1.6), "{element}: {a:?}");
    }
}

/// A refine size below the mesher's coordinate resolution (its snapping grid is 2⁻³⁴ of the
/// body's extent) was refused by the mesher as a "degenerate polygon" whose edges cross: true,
/// but it named neither the table nor the key.  Validation now refuses it, naming both and the
/// smallest size that can be meshed; a size just above that limit still meshes.
#[test]
fn refine_hmax_below_the_coordinate_resolution_is_refused_by_name() {
    let (section, key, reason) = invalid(&with_refine("region = [1.2, 1.2, 1, 1]\nhmax = 1e-13"));
    assert_eq!(key, "hmax");
    assert!(section.contains("refine #1"), "{section}");
    assert!(reason.contains("resolution"), "{reason}");
    // The limit is relative to the body's extent (the upper body is 2 wide: 1.9e-9); a point of
    // its bottom edge refined to 2e-9, just above the limit (the size grows by 1.25 per element away from it) meshes.
    let scene = Scene::from_toml(&with_refine("region = [1.2, 1.2, 1, 1]\nhmax = 2e-9")).unwrap();
    if let Err(e) = mesh_scene(&scene, &MeshLimits::default()) {
        panic!("{e}");
    }
}
