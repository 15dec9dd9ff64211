//! `accuracy.svg` of `signorini study`: discretisation error against total time.
//!
//! One panel per error measure that has a value ([`crate::study::MEASURES`]: Hertz half-width,
//! Hertz peak pressure by the elliptical fit and as the largest nodal pressure, patch-test
//! pressure deviation), stacked vertically in one SVG.  In each panel: |relative error| against
//! total time (mesh + assemble + solve), log–log, one curve per combination (formulation, mesh
//! kind, element), each keeping its colour and marker in every panel; its legend entry carries
//! the fitted convergence rate against h ([`crate::plots::fit_slope`] of (hmax, |error|) over the
//! solved points), e.g. `mortar, graded, p1 (rate 1.95 vs h)`.  Points not solved are hollow;
//! an error of exactly 0 is drawn at [`super::ERROR_FLOOR`] (the legend says so).

use super::render::{self, Curve, Figure};
use crate::output::OutputError;
use crate::study::{combination_order, StudyPoint, MEASURES};

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
                let y = if e == 0.0 { super::ERROR_FLOOR } else { e };
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
            curve.label = match super::fit_slope(&fit) {
                Some(r) => format!("{name} (rate {r:.2} vs h)"),
                None => name.clone(),
            };
            curve
        })
        .collect();
    let mut notes = Vec::new();
    if clamped {
        notes.push(format!("error 0 drawn at {:e}", super::ERROR_FLOOR));
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
