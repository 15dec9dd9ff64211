//! `[[contact]]`: two distinct bodies, not paired before; the optional box (which must hold
//! boundary of both), slave and physical group (which needs a Gmsh body).

use super::outlines::Outlines;
use super::values::{check_finite, check_region, plural, Names};
use crate::geometry;
use crate::scene::draft::{DraftBody, Shape};
use crate::scene::file::ContactSection;
use crate::scene::types::{ContactPair, Friction};
use crate::scene::SceneError;

/// `contact #i ("a" – "b")`, `i` from 0, with the names as the section lists them.
pub(in crate::scene) fn contact_label<S: AsRef<str>>(i: usize, names: &[S]) -> String {
    let names: Vec<String> = names.iter().map(|n| format!("{:?}", n.as_ref())).collect();
    format!("contact #{} ({})", i + 1, names.join(" – "))
}

/// Checks one `[[contact]]` section against the bodies and the `earlier` pairs; with
/// `outlines`, also that its box holds boundary of both bodies.
pub(super) fn validate_contact(
    i: usize,
    c: ContactSection,
    bodies: &[DraftBody],
    earlier: &[ContactPair],
    outlines: Option<&Outlines>,
) -> Result<ContactPair, SceneError> {
    let s = contact_label(i, &c.bodies);
    let [a, b] = pair(&s, &c.bodies, bodies)?;
    let region = match &c.region {
        None => None,
        Some(r) => Some(check_region(&s, r)?),
    };
    let slave = match c.slave {
        None => None,
        Some(name) => {
            let k = Names(bodies).find(&s, "slave", &name)?;
            if k != a && k != b {
                return Err(SceneError::invalid(
                    &s,
                    "slave",
                    format!("{name:?} is not one of the pair's bodies"),
                ));
            }
            Some(k)
        }
    };
    if earlier
        .iter()
        .any(|p| p.bodies == [a, b] || p.bodies == [b, a])
    {
        return Err(SceneError::invalid(
            &s,
            "bodies",
            "repeats a pair already given",
        ));
    }
    if let (Some(r), Some(outlines)) = (&region, outlines) {
        check_contact_region(&s, r, [a, b], outlines)?;
    }
    // A group restricts each body of the pair whose Gmsh mesh defines it; at least one must
    // (the import checks which do).
    if let Some(name) = &c.group {
        let polygons = [a, b]
            .iter()
            .all(|&k| matches!(bodies[k].shape, Shape::Polygon(_)));
        if polygons {
            return Err(contact_group_missing(&s, name, &[]));
        }
    }
    let friction = friction_law(&s, c.friction, c.tresca)?;
    Ok(ContactPair {
        bodies: [a, b],
        region,
        group: c.group,
        slave,
        formulation: c.formulation,
        friction,
    })
}

/// The pair's friction law from `friction` (Coulomb's μ) or `tresca` (a slip bound): each finite
/// and ≥ 0, not both; 0 or absent is frictionless (`None`).
fn friction_law(
    s: &str,
    coulomb: Option<f64>,
    tresca: Option<f64>,
) -> Result<Option<Friction>, SceneError> {
    for (key, value) in [("friction", coulomb), ("tresca", tresca)] {
        if let Some(v) = value {
            check_finite(s, key, &[v])?;
            if v < 0.0 {
                return Err(SceneError::invalid(s, key, format!("must be ≥ 0, got {v}")));
            }
        }
    }
    match (coulomb, tresca) {
        (Some(_), Some(_)) => Err(SceneError::invalid(
            s,
            "tresca",
            "cannot be given with `friction` on one pair: choose Coulomb (`friction = μ`) or Tresca (`tresca = bound`)",
        )),
        (Some(mu), None) if mu > 0.0 => Ok(Some(Friction::Coulomb(mu))),
        (None, Some(bound)) if bound > 0.0 => Ok(Some(Friction::Tresca(bound))),
        _ => Ok(None),
    }
}

/// The two distinct bodies a pair names.
fn pair(s: &str, names: &[String], bodies: &[DraftBody]) -> Result<[usize; 2], SceneError> {
    let [name_a, name_b] = names else {
        return Err(SceneError::invalid(
            s,
            "bodies",
            format!("names {}, needs 2", plural(names.len(), "body", "bodies")),
        ));
    };
    let a = Names(bodies).find(s, "bodies", name_a)?;
    let b = Names(bodies).find(s, "bodies", name_b)?;
    if a == b {
        return Err(SceneError::invalid(
            s,
            "bodies",
            format!("names body {name_a:?} twice; a pair needs two bodies"),
        ));
    }
    Ok([a, b])
}

/// Refuses a contact box that misses one body's boundary: the contact search takes candidate
/// nodes of both bodies inside it, so the pair would fail only after meshing.
pub(in crate::scene) fn check_contact_region(
    s: &str,
    r: &[f64; 4],
    pair: [usize; 2],
    outlines: &Outlines,
) -> Result<(), SceneError> {
    for k in pair {
        if geometry::boundary_in_box(outlines.polygon(k), r, outlines.tol).is_none() {
            return Err(SceneError::invalid(
                s,
                "region",
                format!(
                    "{r:?} holds no boundary of body {:?}; the box must contain part of both \
                     bodies' boundaries",
                    outlines.name(k)
                ),
            ));
        }
    }
    Ok(())
}

/// The error for a pair's group that neither body's mesh defines; `files` describes the
/// pair's Gmsh files (none: both bodies are polygons).
pub(in crate::scene) fn contact_group_missing(s: &str, name: &str, files: &[String]) -> SceneError {
    SceneError::invalid(
        s,
        "group",
        if files.is_empty() {
            format!("= {name:?} needs a body with `mesh` (a Gmsh file); both bodies are polygons")
        } else {
            format!(
                "= {name:?} is a physical group of neither body: {}",
                files.join("; ")
            )
        },
    )
}
