//! The `scene_hash` column: FNV-1a 64 of the scene's canonical text (see the
//! [module docs](super)).

use signorini_core::scene::Scene;

/// The canonical text of `scene` that [`scene_hash`] hashes (see the [module docs](self)):
/// one line per item, names quoted as Rust string literals, floats as `{:e}`, the hmax of the
/// bodies in `swept` (all bodies when empty) written as `swept`, the title left out.
pub fn canonical_scene_text(scene: &Scene, swept: &[String]) -> String {
    use std::fmt::Write as _;
    let mut t = String::from("signorini scene v1\n");
    let pt = |p: &[f64; 2]| format!("{:e} {:e}", p[0], p[1]);
    let bx = |r: &[f64; 4]| format!("{:e} {:e} {:e} {:e}", r[0], r[1], r[2], r[3]);
    // Writing to a String cannot fail.
    let _ = writeln!(t, "plane {:?}", scene.plane);
    let _ = writeln!(t, "thickness {:e}", scene.thickness);
    match &scene.gravity {
        Some(g) => {
            let _ = writeln!(t, "gravity {}", pt(g));
        }
        None => t.push_str("gravity none\n"),
    }
    for b in &scene.bodies {
        let hmax = if swept.is_empty() || swept.contains(&b.name) {
            "swept".to_string()
        } else {
            format!("{:e}", b.hmax)
        };
        let density = b.density.map_or("none".into(), |d| format!("{d:e}"));
        let polygon: Vec<String> = b.polygon.iter().map(pt).collect();
        let _ = writeln!(
            t,
            "body {:?} element {:?} hmax {hmax} young {:e} poisson {:e} density {density} polygon {}",
            b.name,
            b.element,
            b.young,
            b.poisson,
            polygon.join(", ")
        );
    }
    for d in &scene.dirichlet {
        let _ = writeln!(
            t,
            "dirichlet body {} region {} value {} components {} {}",
            d.body,
            bx(&d.region),
            pt(&d.value),
            d.components[0],
            d.components[1]
        );
    }
    for n in &scene.neumann {
        let c = &n.traction.coefficients;
        let _ = writeln!(
            t,
            "neumann body {} region {} traction {:e} {:e} {:e} {:e} {:e} {:e}",
            n.body,
            bx(&n.region),
            c[0][0],
            c[0][1],
            c[0][2],
            c[1][0],
            c[1][1],
            c[1][2]
        );
    }
    for c in &scene.contacts {
        let region = c.region.as_ref().map_or("none".into(), bx);
        let slave = c.slave.map_or("none".into(), |s| s.to_string());
        let _ = writeln!(
            t,
            "contact bodies {} {} region {region} slave {slave}",
            c.bodies[0], c.bodies[1]
        );
    }
    for p in &scene.probes {
        let _ = writeln!(
            t,
            "probe {:?} body {} point {}",
            p.name,
            p.body,
            pt(&p.point)
        );
    }
    t
}

/// FNV-1a, 64 bits.
fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The `scene_hash` column: FNV-1a 64 of [`canonical_scene_text`], 16 lowercase hex digits.
/// Independent of the swept bodies' hmax (and of the title).
pub fn scene_hash(scene: &Scene, swept: &[String]) -> String {
    format!(
        "{:016x}",
        fnv1a64(canonical_scene_text(scene, swept).as_bytes())
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run;
    use crate::sweep::with_hmax;

    #[test]
    fn fnv1a64_matches_the_published_test_vectors() {
        // From the FNV reference test suite (Fowler, Noll, Vo: test vectors for FNV-1a 64).
        assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn scene_hash_ignores_swept_hmax_and_title_but_nothing_else() {
        let scene = run::load_scene(None).unwrap();
        let all: Vec<String> = Vec::new();
        let upper = vec!["upper".to_string()];
        let h = scene_hash(&scene, &all);
        assert_eq!(h.len(), 16);
        assert!(h.chars().all(|c| c.is_ascii_hexdigit()));
        // Independent of the swept sizes and of the title.
        assert_eq!(scene_hash(&with_hmax(&scene, &all, 0.01), &all), h);
        let hu = scene_hash(&scene, &upper);
        assert_eq!(scene_hash(&with_hmax(&scene, &upper, 0.05), &upper), hu);
        let mut retitled = scene.clone();
        retitled.title = "another title".into();
        assert_eq!(scene_hash(&retitled, &all), h);
        // Which bodies are swept, a size that is not swept, and the physics all count.
        assert_ne!(hu, h);
        let mut lower_finer = scene.clone();
        lower_finer.bodies[1].hmax = 0.1;
        assert_ne!(scene_hash(&lower_finer, &upper), hu);
        let mut stiffer = scene.clone();
        // The next float up: the smallest possible change.
        stiffer.bodies[0].young = f64::from_bits(scene.bodies[0].young.to_bits() + 1);
        assert_ne!(scene_hash(&stiffer, &all), h);
        let mut loaded = scene.clone();
        loaded.neumann[0].traction.coefficients[1][2] *= 2.0;
        assert_ne!(scene_hash(&loaded, &all), h);
        let mut renamed = scene.clone();
        renamed.probes[0].name.push('x');
        assert_ne!(scene_hash(&renamed, &all), h);
    }
}
