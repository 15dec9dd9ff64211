//! SVG plot of the undeformed and the (magnified) deformed meshes.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use signorini_core::mesh::Mesh;

use super::{validate, write_atomically, xml_sanitize, BodyField, OutputError};
use crate::output::chart_style::plot_err;

/// Largest displacement shown, as a fraction of the scene's size, when magnifying.
const TARGET_FRACTION: f64 = 0.1;

/// Canvas width in pixels.
const WIDTH: u32 = 960;
/// Width of the legend panel right of the plot, in pixels.
const LEGEND_W: u32 = 210;
/// Margin around the chart, in pixels.
const MARGIN: u32 = 12;
/// Height of the x tick label area, in pixels.
const X_LABELS: u32 = 40;
/// Width of the y tick label area, in pixels.
const Y_LABELS: u32 = 70;

/// Colour of the undeformed mesh.
const UNDEFORMED: RGBColor = RGBColor(200, 200, 200);
/// Colour of boundary edges in contact (pressure > 0 at both ends).
const CONTACT: RGBColor = RGBColor(200, 0, 0);
/// One colour per body or backend (cycled): a colour-blind friendly qualitative palette, shared
/// by every plot.
pub(crate) const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(230, 159, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(213, 94, 0),
    RGBColor(120, 120, 20),
    RGBColor(60, 60, 60),
];

/// Bounding box `[xmin, xmax, ymin, ymax]` of the undeformed meshes (`None` without nodes).
fn scene_box(bodies: &[BodyField]) -> Option<[f64; 4]> {
    let mut it = bodies.iter().flat_map(|b| b.mesh.nodes.iter());
    let first = it.next()?;
    Some(it.fold([first[0], first[0], first[1], first[1]], |b, p| {
        [
            b[0].min(p[0]),
            b[1].max(p[0]),
            b[2].min(p[1]),
            b[3].max(p[1]),
        ]
    }))
}

/// Largest nodal displacement norm; NaN if any displacement is NaN (`f64::max` would skip it).
fn max_displacement(bodies: &[BodyField]) -> f64 {
    bodies
        .iter()
        .flat_map(|b| b.displacement.iter())
        .map(|u| u[0].hypot(u[1]))
        .fold(0.0, |m: f64, v| {
            if m.is_nan() || v.is_nan() {
                f64::NAN
            } else {
                m.max(v)
            }
        })
}

/// A factor so that the largest nodal displacement shows as about 10 % of the scene's size
/// (the larger side of the bounding box of the undeformed meshes), rounded to 1, 2 or 5 × 10^k
/// for a readable label.  Returns 1.0 when the displacement is zero, not finite, or already at
/// least that visible; the factor never shrinks displacements.
pub fn magnification(bodies: &[BodyField]) -> f64 {
    let Some(bb) = scene_box(bodies) else {
        return 1.0;
    };
    let size = (bb[1] - bb[0]).max(bb[3] - bb[2]);
    let umax = max_displacement(bodies);
    if !(size.is_finite() && umax.is_finite()) || size <= 0.0 || umax <= 0.0 {
        return 1.0;
    }
    let raw = TARGET_FRACTION * size / umax;
    if !raw.is_finite() || raw <= 1.0 {
        return 1.0;
    }
    // Nearest of 1, 2, 5, 10 × 10^k in log scale (so 99.99999 gives 100, not 50).
    let k = raw.log10().floor();
    let decade = 10f64.powf(k);
    let mantissa = raw / decade;
    let best = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .min_by(|a: &f64, b: &f64| {
            let da = (mantissa / a).ln().abs();
            let db = (mantissa / b).ln().abs();
            da.total_cmp(&db)
        })
        .unwrap_or(1.0);
    // Round away the floating-point noise of `decade` (e.g. 5.000000000000001).
    let factor = best * decade;
    let digits = factor.log10().floor();
    let unit = 10f64.powf(digits);
    ((factor / unit).round() * unit).max(1.0)
}

/// Formats the magnification factor for the label: integers below 10^6 plainly, else `5e7`.
fn factor_label(f: f64) -> String {
    if f < 1e6 && f.fract() == 0.0 {
        format!("{f:.0}")
    } else {
        format!("{f:e}")
    }
}

/// Unique undirected edges of the mesh cells, sorted.
pub(super) fn unique_edges(mesh: &Mesh) -> Vec<[usize; 2]> {
    let mut edges = Vec::new();
    for i in 0..mesh.cells.len() {
        let c = mesh.cells.cell(i);
        for (j, &a) in c.iter().enumerate() {
            let b = c[(j + 1) % c.len()];
            edges.push([a.min(b), a.max(b)]);
        }
    }
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// Chains edges into few polylines (each edge used once) to keep the SVG small.
pub(super) fn chain_edges(edges: &[[usize; 2]], n_nodes: usize) -> Vec<Vec<usize>> {
    let mut adj: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n_nodes];
    for (e, &[a, b]) in edges.iter().enumerate() {
        adj[a].push((b, e));
        adj[b].push((a, e));
    }
    let mut used = vec![false; edges.len()];
    let mut next = vec![0usize; n_nodes];
    // Start at odd-degree nodes first: a path must begin or end there.
    let starts = (0..n_nodes)
        .filter(|&v| adj[v].len() % 2 == 1)
        .chain(0..n_nodes);
    let mut chains = Vec::new();
    for start in starts {
        loop {
            let mut path = vec![start];
            let mut cur = start;
            loop {
                while next[cur] < adj[cur].len() && used[adj[cur][next[cur]].1] {
                    next[cur] += 1;
                }
                let Some(&(nbr, e)) = adj[cur].get(next[cur]) else {
                    break;
                };
                used[e] = true;
                path.push(nbr);
                cur = nbr;
            }
            if path.len() < 2 {
                break;
            }
            chains.push(path);
        }
    }
    chains
}

/// Expands `[x0, x1, y0, y1]` around its centre so that it fills `w × h` pixels at equal scale.
fn equal_aspect(r: [f64; 4], w: u32, h: u32) -> [f64; 4] {
    let (w, h) = (f64::from(w.max(1)), f64::from(h.max(1)));
    let scale = ((r[1] - r[0]) / w).max((r[3] - r[2]) / h);
    let (cx, cy) = (0.5 * (r[0] + r[1]), 0.5 * (r[2] + r[3]));
    let (hx, hy) = (0.5 * scale * w, 0.5 * scale * h);
    [cx - hx, cx + hx, cy - hy, cy + hy]
}

/// Plots the undeformed meshes (light grey) and the deformed meshes (nodes + magnification ×
/// displacement, one colour per body, boundary drawn thicker) at equal aspect ratio, with a
/// legend naming the bodies, the magnification ("displacement × 50") and the largest
/// displacement.  Boundary edges whose two nodes both carry contact pressure are drawn thick red.
/// Each mesh edge is drawn once.  Written via [`write_atomically`]; see
/// [`render_deformed_svg`] for the text.
pub fn write_deformed_svg(
    path: &Path,
    title: &str,
    bodies: &[BodyField],
) -> Result<(), OutputError> {
    let svg = render_deformed_svg(title, bodies)?;
    write_atomically(path, |w| w.write_all(svg.as_bytes()))
}

/// The plot of [`write_deformed_svg`] as an SVG document (lengths validated first).  The title
/// and body names may hold any text: characters XML does not allow become U+FFFD (see
/// [`xml_sanitize`](super::xml_sanitize)) and `& < > " '` are escaped, so the document is
/// always well-formed and its text reads back as given.
pub fn render_deformed_svg(title: &str, bodies: &[BodyField]) -> Result<String, OutputError> {
    validate(bodies)?;
    render_svg(title, bodies)
}

/// Renders the plot to an SVG string.
fn render_svg(title: &str, bodies: &[BodyField]) -> Result<String, OutputError> {
    let mut factor = magnification(bodies);
    let mut deformed: Vec<Vec<(f64, f64)>> = bodies
        .iter()
        .map(|b| {
            b.mesh
                .nodes
                .iter()
                .zip(b.displacement)
                .map(|(p, u)| (p[0] + factor * u[0], p[1] + factor * u[1]))
                .collect()
        })
        .collect();
    let undeformed: Vec<Vec<(f64, f64)>> = bodies
        .iter()
        .map(|b| b.mesh.nodes.iter().map(|p| (p[0], p[1])).collect())
        .collect();
    // A displacement that dwarfs the bodies (or is not finite) cannot be drawn with them: the
    // axes would span 1e300 (plotters' tick loop never ends there). Draw the undeformed shape
    // only and say so in the legend (factor 0).
    let extent = |shapes: &[Vec<(f64, f64)>]| {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for &(x, y) in shapes.iter().flatten() {
            lo = [lo[0].min(x), lo[1].min(y)];
            hi = [hi[0].max(x), hi[1].max(y)];
        }
        (hi[0] - lo[0]).max(hi[1] - lo[1])
    };
    let (body_size, drawn_size) = (extent(&undeformed), extent(&deformed));
    if !(drawn_size.is_finite() && drawn_size <= 1e3 * body_size.max(f64::MIN_POSITIVE)) {
        factor = 0.0;
        deformed = undeformed.clone();
    }

    // Data range: both shapes, padded; a degenerate or empty scene gets a unit box.
    let all = undeformed.iter().chain(&deformed).flatten();
    let mut r = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    for &(x, y) in all.filter(|(x, y)| x.is_finite() && y.is_finite()) {
        r = [r[0].min(x), r[1].max(x), r[2].min(y), r[3].max(y)];
    }
    if !r.iter().all(|v| v.is_finite()) {
        r = [0.0, 1.0, 0.0, 1.0];
    }
    let size = (r[1] - r[0]).max(r[3] - r[2]);
    let pad = if size > 0.0 { 0.05 * size } else { 0.5 };
    let r = [r[0] - pad, r[1] + pad, r[2] - pad, r[3] + pad];

    // Canvas height from the data's aspect ratio (clamped), then exact equal aspect below.
    let plot_w = WIDTH - 2 * MARGIN - Y_LABELS - LEGEND_W;
    let aspect = (r[3] - r[2]) / (r[1] - r[0]);
    let plot_h = (f64::from(plot_w) * aspect).clamp(240.0, 900.0) as u32;
    let height = plot_h + 2 * MARGIN + X_LABELS + 48;

    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        // plotters escapes `& < > " '`; characters XML forbids are replaced here.
        let heading = if title.is_empty() {
            "deformed shape".to_string()
        } else {
            xml_sanitize(title)
        };
        let area = root
            .titled(&heading, ("sans-serif", 22).into_font())
            .map_err(plot_err)?;
        draw_chart(&area, r, bodies, &undeformed, &deformed, factor)?;
        root.present().map_err(plot_err)?;
    }
    Ok(buf)
}

/// Draws axes, meshes and the legend panel into `area`.
fn draw_chart(
    area: &DrawingArea<SVGBackend, Shift>,
    r: [f64; 4],
    bodies: &[BodyField],
    undeformed: &[Vec<(f64, f64)>],
    deformed: &[Vec<(f64, f64)>],
    factor: f64,
) -> Result<(), OutputError> {
    let builder = || {
        let mut b = ChartBuilder::on(area);
        b.margin(MARGIN)
            .margin_right(MARGIN + LEGEND_W)
            .x_label_area_size(X_LABELS)
            .y_label_area_size(Y_LABELS);
        b
    };
    // Measure the plotting area (building draws nothing), then fit the ranges to it.
    let (pw, ph) = builder()
        .build_cartesian_2d(r[0]..r[1], r[2]..r[3])
        .map_err(plot_err)?
        .plotting_area()
        .dim_in_pixel();
    let r = equal_aspect(r, pw, ph);
    let mut chart = builder()
        .build_cartesian_2d(r[0]..r[1], r[2]..r[3])
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x")
        .y_desc("y")
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(plot_err)?;

    let polylines = |pts: &[(f64, f64)], chains: &[Vec<usize>], style: ShapeStyle| {
        chains
            .iter()
            .map(|c| PathElement::new(c.iter().map(|&i| pts[i]).collect::<Vec<_>>(), style))
            .collect::<Vec<_>>()
    };
    let chains: Vec<Vec<Vec<usize>>> = bodies
        .iter()
        .map(|b| chain_edges(&unique_edges(b.mesh), b.mesh.nodes.len()))
        .collect();

    for (pts, ch) in undeformed.iter().zip(&chains) {
        chart
            .draw_series(polylines(pts, ch, UNDEFORMED.stroke_width(1)))
            .map_err(plot_err)?;
    }
    let mut any_contact = false;
    for (k, (b, (pts, ch))) in bodies.iter().zip(deformed.iter().zip(&chains)).enumerate() {
        let colour = PALETTE[k % PALETTE.len()];
        chart
            .draw_series(polylines(pts, ch, colour.stroke_width(1)))
            .map_err(plot_err)?;
        let outline = chain_edges(&b.mesh.boundary, b.mesh.nodes.len());
        chart
            .draw_series(polylines(pts, &outline, colour.stroke_width(2)))
            .map_err(plot_err)?;
        let in_contact: Vec<[usize; 2]> = b
            .mesh
            .boundary
            .iter()
            .copied()
            .filter(|e| b.contact_pressure[e[0]] > 0.0 && b.contact_pressure[e[1]] > 0.0)
            .collect();
        if !in_contact.is_empty() {
            any_contact = true;
            let contact = chain_edges(&in_contact, b.mesh.nodes.len());
            chart
                .draw_series(polylines(pts, &contact, CONTACT.stroke_width(4)))
                .map_err(plot_err)?;
        }
    }

    // Legend panel right of the plot (pixel coordinates of `area`).
    let umax = max_displacement(bodies);
    let (aw, _) = area.dim_in_pixel();
    let x0 = (aw - LEGEND_W) as i32 + 10;
    let mut y = (MARGIN + 10) as i32;
    let text = ("sans-serif", 15).into_font().color(&BLACK);
    let mut entry = |label: &str, style: ShapeStyle| -> Result<(), OutputError> {
        area.draw(&PathElement::new(vec![(x0, y), (x0 + 28, y)], style))
            .map_err(plot_err)?;
        area.draw(&Text::new(
            label.to_string(),
            (x0 + 36, y - 8),
            text.clone(),
        ))
        .map_err(plot_err)?;
        y += 24;
        Ok(())
    };
    entry("undeformed", UNDEFORMED.stroke_width(2))?;
    for (k, b) in bodies.iter().enumerate() {
        entry(
            &xml_sanitize(b.name),
            PALETTE[k % PALETTE.len()].stroke_width(2),
        )?;
    }
    if any_contact {
        entry("contact (active)", CONTACT.stroke_width(4))?;
    }
    y += 12;
    let bold = ("sans-serif", 16)
        .into_font()
        .style(FontStyle::Bold)
        .color(&BLACK);
    let label = if factor == 0.0 {
        "deformed shape too large to draw".to_string()
    } else {
        format!("displacement × {}", factor_label(factor))
    };
    area.draw(&Text::new(label, (x0, y), bold))
        .map_err(plot_err)?;
    area.draw(&Text::new(
        format!("max |u| = {umax:.3e}"),
        (x0, y + 24),
        text,
    ))
    .map_err(plot_err)?;
    Ok(())
}
