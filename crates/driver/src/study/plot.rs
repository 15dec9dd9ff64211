//! `accuracy.svg` of `signorini study`: discretisation error against total time.
//!
//! One panel per error measure that has a value ([`crate::study::points::MEASURES`]: Hertz half-width,
//! Hertz peak pressure by the elliptical fit and as the largest nodal pressure, patch-test
//! pressure deviation, Cattaneo's stick half-width and rms tangential traction error), stacked
//! vertically in one SVG.  In each panel: |relative error| against
//! total time (mesh + assemble + solve), log–log, one curve per combination (formulation, mesh
//! kind, element), each keeping its colour and marker in every panel; its legend entry carries
//! the fitted convergence rate against h ([`crate::plots::fit_slope`] of (hmax, |error|) over the
//! solved points), e.g. `mortar, graded, p1 (rate 1.95 vs h)`.  Points not solved are hollow;
//! an error of exactly 0 is drawn at [`crate::plots::ERROR_FLOOR`] (the legend says so).

use super::points::{combination_order, StudyPoint, MEASURES};
use crate::output::OutputError;
use crate::plots::render::{self, Curve, Figure};

/// Height of one panel, as [`render`] draws it (the canvas is 900 × 620).
const PANEL: (u32, u32) = (900, 620);

/// The figure of one measure, or `None` when no point has a value for it.
fn panel(
    points: &[StudyPoint],
    combos: &[String],
    measure: &str,
    read: fn(&StudyPoint) -> Option<f64>,
    title: &str,
) -> Option<Figure> {
    if points.iter().all(|p| read(p).is_none()) {
        return None;
    }
    let mut clamped = false;
    let curves = combos
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let mut mine: Vec<&StudyPoint> =
                points.iter().filter(|p| p.combination() == *name).collect();
            mine.sort_by(|a, b| a.total_s.total_cmp(&b.total_s));
            let mut curve = Curve::backend(k, String::new());
            let mut fit = Vec::new();
            for p in mine {
                let Some(e) = read(p) else { continue };
                let e = e.abs();
                let y = if e == 0.0 {
                    crate::plots::ERROR_FLOOR
                } else {
                    e
                };
                let q = (p.total_s, y);
                if !(q.0.is_finite() && q.1.is_finite() && q.0 > 0.0) {
                    continue;
                }
                clamped |= e == 0.0;
                if p.solved() {
                    curve.line.push(q);
                    fit.push((p.hmax, e));
                } else {
                    curve.hollow.push(q);
                }
            }
            curve.label = match crate::plots::fit_slope(&fit) {
                Some(r) => format!("{name} (rate {r:.2} vs h)"),
                None => name.clone(),
            };
            curve
        })
        .collect();
    let mut notes = Vec::new();
    if clamped {
        notes.push(format!("error 0 drawn at {:e}", crate::plots::ERROR_FLOOR));
    }
    let what = format!("{measure}: error vs time");
    Some(Figure {
        heading: if title.trim().is_empty() {
            what
        } else {
            format!("{title}: {what}")
        },
        x_desc: "total time: mesh + assemble + solve (s)".into(),
        y_desc: "|relative error| (dimensionless)".into(),
        curves,
        hline: None,
        notes,
    })
}

/// `accuracy.svg` for a study's points (see the [module docs](self)); `None` when no panel has a
/// drawable point.  `title` prefixes each panel's heading.
pub fn render_accuracy(points: &[StudyPoint], title: &str) -> Result<Option<String>, OutputError> {
    let combos = combination_order(points);
    let mut panels = Vec::new();
    for (measure, read) in MEASURES {
        let Some(fig) = panel(points, &combos, measure, read, title) else {
            continue;
        };
        if let Some(svg) = render::render(&fig)? {
            panels.push(svg);
        }
    }
    if panels.is_empty() {
        return Ok(None);
    }
    Ok(Some(stack(&panels)))
}

/// The panels (complete SVG documents of [`PANEL`] size) one below the other in one document:
/// each panel's `<svg>` root becomes a nested `<svg>` placed at its offset.
fn stack(panels: &[String]) -> String {
    let (w, h) = PANEL;
    let total = h * panels.len() as u32;
    let mut out = format!(
        "<svg width=\"{w}\" height=\"{total}\" viewBox=\"0 0 {w} {total}\" \
         xmlns=\"http://www.w3.org/2000/svg\">\n"
    );
    for (i, svg) in panels.iter().enumerate() {
        // Drop any XML declaration: it may only open a document.
        let body = match svg.find("<svg") {
            Some(at) => &svg[at..],
            None => svg.as_str(),
        };
        let y = h * i as u32;
        out.push_str(&body.replacen("<svg", &format!("<svg x=\"0\" y=\"{y}\""), 1));
        out.push('\n');
    }
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(combo: (&str, &str), h: f64, t: f64, e: Option<f64>, status: &str) -> StudyPoint {
        StudyPoint {
            formulation: combo.0.into(),
            mesh: combo.1.into(),
            element: "p1".into(),
            hmax: h,
            hmin: h,
            dofs: 1,
            constraints: 1,
            backend: "b".into(),
            status: status.into(),
            mesh_s: 0.0,
            assemble_s: 0.0,
            solve_s: t,
            total_s: t,
            half_width: None,
            error_half_width: e,
            peak_pressure: None,
            error_peak_pressure: e.map(|e| 2.0 * e),
            peak_nodal_pressure: None,
            error_peak_nodal_pressure: None,
            pressure_deviation: None,
            stick_half_width: None,
            error_stick_half_width: None,
            error_tangential_traction: None,
            message: String::new(),
        }
    }

    #[test]
    fn one_panel_per_measure_with_values_and_rates_in_the_legend() {
        let a = ("mortar", "graded");
        let b = ("node-to-segment", "uniform");
        // |error| = h² for `a`: rate 2.00; `b` has a zero error (clamped, noted) and an
        // unsolved point (hollow, not fitted).
        let points = vec![
            point(a, 0.1, 0.01, Some(-0.01), "solved"),
            point(a, 0.05, 0.04, Some(-0.0025), "solved"),
            point(b, 0.1, 0.02, Some(0.0), "solved"),
            point(b, 0.05, 0.08, Some(0.3), "max-iterations"),
        ];
        let svg = render_accuracy(&points, "T").unwrap().unwrap();
        let doc = roxmltree::Document::parse(&svg).expect("well-formed");
        let nested = doc
            .root_element()
            .children()
            .filter(|n| n.has_tag_name("svg"))
            .count();
        // Two measures have values (a and p₀ by the fit): two panels, stacked.
        assert_eq!(nested, 2);
        assert_eq!(doc.root_element().attribute("height"), Some("1240"));
        assert!(svg.contains("mortar, graded, p1 (rate 2.00 vs h)"), "{svg}");
        assert!(svg.contains("half-width a: error vs time"));
        assert!(svg.contains("error 0 drawn at"));
        assert!(!svg.contains("max nodal"), "no panel without values");
        // Nothing drawable: no plot.
        let none = vec![point(a, 0.1, 0.01, None, "solved")];
        assert!(render_accuracy(&none, "T").unwrap().is_none());
    }
}
