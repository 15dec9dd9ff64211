//! `pressure.svg`: the contact pressure along the slave interface of every contact pair.
//!
//! Everything plotted comes from the report (`result.json`'s `contacts`), nothing from the
//! model: per pair, its slave nodes' `pressure` (λ / `weight`) against their arc coordinate `s`
//! (see [`signorini_core::report::arc`]), one colour per pair (the palette shared by every plot).
//!
//! * An **active** node (`active` in result.json, [`signorini_core::report::is_active`]) is a
//!   filled circle; consecutive active nodes of one interface piece (in the order of `s`) are
//!   joined by a line, so the line breaks at inactive nodes and between pieces.
//! * An **inactive** node is a hollow circle of the pair's colour at its (round-off) pressure,
//!   not joined: the plot shows where the interface is open.
//! * A node whose `s` or `pressure` is not finite is left out (a failed solve); the legend then
//!   says how many.
//! * The legend names each pair: its number in the scene (1-based), its slave and master bodies
//!   and its formulation.  Nothing else depends on the formulation: node-to-segment and mortar
//!   pressures are both λ divided by the row's weight, so their curves are comparable.
//! * The axes are linear and start at 0 (s ≥ 0; the pressure axis includes 0).  Values outside
//!   [10⁻³, 10⁵) are plotted divided by a power of ten, which the axis label states
//!   ("× 1e6"), so that no axis spans extreme magnitudes.
//!
//! * A **frictional** pair (its report has `friction`) adds, in the same units, its tangential
//!   traction q = λₜ / weight (`tangential_traction`, signed along the rows' tangent) as a dashed
//!   line with square markers, the friction bound ±μp (Coulomb, from each node's pressure) or ±s
//!   (Tresca) as thin grey dashed lines, and shades the slip zones: the intervals of `s` between
//!   consecutive nodes whose `state` is `slip` (a lone slipping node gets a band half-way to its
//!   neighbours).  The y axis then spans the negative tractions too.
//!
//! `solve` writes the file with its other outputs exactly when the model has at least one
//! contact row ([`render_pressure_svg`] returns `None` otherwise).

use plotters::prelude::*;

use plotters::coord::types::RangedCoordf64;
use signorini_core::report::{ContactNodeReport, ContactReport, ContactState, RunReport};
use signorini_core::scene::Formulation;

use super::chart_style::{
    draw_legend, fit_heading, plot_err, GREY, LEGEND_ROW, MARGIN, X_LABELS, Y_LABELS,
};
use super::svg::PALETTE;
use super::{xml_sanitize, OutputError};

/// Canvas size in pixels.
const SIZE: (u32, u32) = (900, 580);
/// Marker radius in pixels.
const MARKER: u32 = 4;

/// Legend text of the hollow-marker entry.
pub const INACTIVE_LABEL: &str = "hollow: inactive node (not in contact)";

/// The formulation as written in the scene and in result.json.
fn formulation_name(f: Formulation) -> &'static str {
    match f {
        Formulation::NodeToSegment => "node-to-segment",
        Formulation::Mortar => "mortar",
    }
}

/// One pair's points, ready to draw (in plotted units).
struct PairCurve {
    /// Legend text.
    label: String,
    /// Colour.
    colour: RGBColor,
    /// Runs of consecutive active nodes (each drawn as one line).
    runs: Vec<Vec<(f64, f64)>>,
    /// Active nodes.
    active: Vec<(f64, f64)>,
    /// Inactive nodes.
    inactive: Vec<(f64, f64)>,
    /// Frictional pairs: the tangential traction and its bounds.
    friction: Option<FrictionCurve>,
}

/// A frictional pair's tangential traction, bounds and slip zones (in plotted units).
struct FrictionCurve {
    /// The tangential traction at every finite node, along the interface (per piece).
    traction: Vec<Vec<(f64, f64)>>,
    /// The bound at each node (μp or s), drawn at ±.
    bound: Vec<Vec<(f64, f64)>>,
    /// The s-intervals where nodes slip.
    slip_zones: Vec<(f64, f64)>,
}

/// Legend text of the slip-zone shading.
pub const SLIP_LABEL: &str = "shaded: slip zone (state = slip)";

/// The legend text of pair `k` (0-based index among the report's pairs).
pub fn pair_label(k: usize, c: &ContactReport) -> String {
    let master = c
        .bodies
        .iter()
        .find(|b| **b != c.slave)
        .unwrap_or(&c.bodies[1]);
    format!(
        "pair {}: {} (slave) on {}, {}",
        k + 1,
        c.slave,
        master,
        formulation_name(c.formulation)
    )
}

/// A power of ten that brings the largest magnitude among `values` into [10⁻³, 10⁵): 1 when
/// it is there already (or zero), else 10^⌊log₁₀ max⌋ (exponent clamped to ±300).  Returns
/// (divisor, exponent).
fn scale(values: impl Iterator<Item = f64>) -> (f64, i32) {
    let max = values.fold(0.0_f64, |m, v| m.max(v.abs()));
    if max == 0.0 || (1e-3..1e5).contains(&max) {
        return (1.0, 0);
    }
    let e = (max.log10().floor() as i32).clamp(-300, 300);
    (10f64.powi(e), e)
}

/// `desc` with the scale note when `e` ≠ 0.
fn with_scale(desc: &str, e: i32) -> String {
    if e == 0 {
        desc.to_string()
    } else {
        format!("{desc} (× 1e{e})")
    }
}

/// A linear range holding 0 and every value, padded by 3 % of its width on each side (so that
/// markers at 0 clear the axis); [−0.03, 1.03] when there is no value or all are 0.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((0.0_f64, 0.0_f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    let width = hi - lo;
    let (lo, hi, width) = if width > 0.0 && width.is_finite() {
        (lo, hi, width)
    } else {
        (0.0, 1.0, 1.0)
    };
    let pad = 0.03 * width;
    (lo - pad, hi + pad)
}

/// Whether a node can be plotted (finite `s` and pressure).
fn finite(n: &ContactNodeReport) -> bool {
    n.s.is_finite() && n.pressure.is_finite()
}

/// The curve of pair `k` (its finite nodes, scaled by `sx` and `sy`): the runs of consecutive
/// active nodes of one interface piece, the active and the inactive markers.
fn pair_curve(k: usize, c: &ContactReport, sx: f64, sy: f64) -> PairCurve {
    let mut sorted: Vec<_> = c.nodes.iter().filter(|n| finite(n)).collect();
    sorted.sort_by(|a, b| a.piece.cmp(&b.piece).then(a.s.total_cmp(&b.s)));
    let mut curve = PairCurve {
        label: xml_sanitize(&pair_label(k, c)),
        colour: PALETTE[k % PALETTE.len()],
        runs: Vec::new(),
        active: Vec::new(),
        inactive: Vec::new(),
        friction: None,
    };
    let mut run: Vec<(f64, f64)> = Vec::new();
    let mut piece = None;
    for n in sorted.iter().copied() {
        let p = (n.s / sx, n.pressure / sy);
        if piece != Some(n.piece) || !n.active {
            if run.len() > 1 {
                curve.runs.push(std::mem::take(&mut run));
            }
            run.clear();
            piece = Some(n.piece);
        }
        if n.active {
            run.push(p);
            curve.active.push(p);
        } else {
            curve.inactive.push(p);
        }
    }
    if run.len() > 1 {
        curve.runs.push(run);
    }
    curve.friction = friction_curve(c, &sorted, sx, sy);
    curve
}

/// The pair's tangential traction, its bound and its slip zones, when the pair has friction.
fn friction_curve(
    c: &ContactReport,
    nodes: &[&ContactNodeReport],
    sx: f64,
    sy: f64,
) -> Option<FrictionCurve> {
    let law = c.friction?;
    let mut curve = FrictionCurve {
        traction: Vec::new(),
        bound: Vec::new(),
        slip_zones: Vec::new(),
    };
    let mut piece = None;
    let with_q: Vec<(&ContactNodeReport, f64)> = nodes
        .iter()
        .filter_map(|n| Some((*n, n.tangential_traction.filter(|q| q.is_finite())?)))
        .collect();
    for (k, &(n, q)) in with_q.iter().enumerate() {
        if piece != Some(n.piece) {
            curve.traction.push(Vec::new());
            curve.bound.push(Vec::new());
            piece = Some(n.piece);
        }
        let bound = law.bound(n.pressure, 1.0);
        if let (Some(t), Some(b)) = (curve.traction.last_mut(), curve.bound.last_mut()) {
            t.push((n.s / sx, q / sy));
            b.push((n.s / sx, bound / sy));
        }
        if n.state == Some(ContactState::Slip) {
            // Half-way to the neighbours on the same piece (or the node itself at an end).
            let half = |j: Option<usize>| {
                j.and_then(|j| with_q.get(j))
                    .filter(|(m, _)| m.piece == n.piece)
                    .map_or(n.s, |(m, _)| 0.5 * (m.s + n.s))
            };
            let (lo, hi) = (half(k.checked_sub(1)), half(Some(k + 1)));
            match curve.slip_zones.last_mut() {
                Some(zone) if zone.1 >= lo / sx => zone.1 = hi / sx,
                _ => curve.slip_zones.push((lo / sx, hi / sx)),
            }
        }
    }
    Some(curve)
}

/// The pressure chart's coordinates.
type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws every pair's lines and markers with its legend entry, then the legend entries of the
/// hollow markers (when some node is inactive) and of the `note`.
fn draw_series<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    curves: &[PairCurve],
    any_inactive: bool,
    note: Option<&str>,
) -> Result<(), OutputError> {
    for c in curves {
        let colour = c.colour;
        let style = colour.stroke_width(2);
        for run in &c.runs {
            chart
                .draw_series(LineSeries::new(run.iter().copied(), style))
                .map_err(plot_err)?;
        }
        chart
            .draw_series(
                c.active
                    .iter()
                    .map(|&p| Circle::new(p, MARKER, colour.filled())),
            )
            .map_err(plot_err)?;
        chart
            .draw_series(
                c.inactive
                    .iter()
                    .map(|&p| Circle::new(p, MARKER, colour.stroke_width(1))),
            )
            .map_err(plot_err)?;
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), u32>>())
            .map_err(plot_err)?
            .label(c.label.clone())
            .legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new([(0, 0), (24, 0)], style)
                    + Circle::new((12, 0), MARKER, colour.filled())
            });
    }
    if any_inactive {
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), u32>>())
            .map_err(plot_err)?
            .label(INACTIVE_LABEL)
            .legend(|(x, y)| Circle::new((x + 12, y), MARKER, GREY.stroke_width(1)));
    }
    if let Some(note) = note {
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), u32>>())
            .map_err(plot_err)?
            .label(note)
            .legend(|(x, y)| EmptyElement::at((x, y)));
    }
    Ok(())
}

/// The tangential tractions and ± bounds of every frictional pair's finite nodes (for the
/// axes' scale and range).
fn friction_values(report: &RunReport) -> Vec<f64> {
    let mut values = Vec::new();
    for c in &report.contacts {
        let Some(law) = c.friction else { continue };
        for n in c.nodes.iter().filter(|n| finite(n)) {
            if let Some(q) = n.tangential_traction.filter(|q| q.is_finite()) {
                let bound = law.bound(n.pressure, 1.0);
                values.extend([q, bound, -bound]);
            }
        }
    }
    values
}

/// Light fill of the slip zones.
const SLIP_SHADE: RGBColor = RGBColor(255, 236, 200);

/// Draws the frictional pairs' slip zones (under everything), their tangential tractions
/// (dashed, triangles) and ± bounds (thin grey dashes), with their legend entries.
fn draw_friction<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    curves: &[PairCurve],
    yr: (f64, f64),
) -> Result<(), OutputError> {
    let frictional: Vec<(&PairCurve, &FrictionCurve)> = curves
        .iter()
        .filter_map(|c| Some((c, c.friction.as_ref()?)))
        .collect();
    if frictional.is_empty() {
        return Ok(());
    }
    let zones: Vec<(f64, f64)> = frictional
        .iter()
        .flat_map(|(_, f)| f.slip_zones.iter().copied())
        .collect();
    if !zones.is_empty() {
        chart
            .draw_series(
                zones
                    .iter()
                    .map(|&(lo, hi)| Rectangle::new([(lo, yr.0), (hi, yr.1)], SLIP_SHADE.filled())),
            )
            .map_err(plot_err)?
            .label(SLIP_LABEL)
            .legend(|(x, y)| Rectangle::new([(x, y - 5), (x + 24, y + 5)], SLIP_SHADE.filled()));
    }
    let grey = GREY.stroke_width(1);
    for (_, f) in &frictional {
        for run in &f.bound {
            for sign in [1.0, -1.0] {
                chart
                    .draw_series(DashedLineSeries::new(
                        run.iter().map(|&(x, b)| (x, sign * b)),
                        4,
                        4,
                        grey,
                    ))
                    .map_err(plot_err)?;
            }
        }
    }
    chart
        .draw_series(std::iter::empty::<Circle<(f64, f64), u32>>())
        .map_err(plot_err)?
        .label("± friction bound (μp or Tresca's s)")
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], grey));
    for (c, f) in &frictional {
        let colour = c.colour;
        let style = colour.stroke_width(2);
        for run in &f.traction {
            chart
                .draw_series(DashedLineSeries::new(run.iter().copied(), 8, 5, style))
                .map_err(plot_err)?;
            chart
                .draw_series(
                    run.iter()
                        .map(|&p| TriangleMarker::new(p, MARKER + 1, colour.filled())),
                )
                .map_err(plot_err)?;
        }
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), u32>>())
            .map_err(plot_err)?
            .label(format!("{}: tangential traction q", c.label))
            .legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new([(0, 0), (24, 0)], style)
                    + TriangleMarker::new((12, 0), MARKER + 1, colour.filled())
            });
    }
    Ok(())
}

/// Renders `pressure.svg` for the report's contact pairs; `None` when the report has no contact
/// row (then no file is written).  `title` is the scene's title (any text: it is sanitised, and
/// plotters escapes `& < > " '`).
pub fn render_pressure_svg(title: &str, report: &RunReport) -> Result<Option<String>, OutputError> {
    if report.contacts.iter().all(|c| c.nodes.is_empty()) {
        return Ok(None);
    }
    let finite = |n: &&ContactNodeReport| finite(n);
    let points = || {
        report
            .contacts
            .iter()
            .flat_map(|c| c.nodes.iter())
            .filter(finite)
    };
    let left_out = report.contacts.iter().flat_map(|c| c.nodes.iter()).count() - points().count();
    let (sx, ex) = scale(points().map(|n| n.s));
    let tangential = friction_values(report);
    let (sy, ey) = scale(
        points()
            .map(|n| n.pressure)
            .chain(tangential.iter().copied()),
    );

    let curves: Vec<PairCurve> = report
        .contacts
        .iter()
        .enumerate()
        .filter(|(_, c)| !c.nodes.is_empty())
        .map(|(k, c)| pair_curve(k, c, sx, sy))
        .collect();

    let xr = range(points().map(|n| n.s / sx));
    let yr = range(
        points()
            .map(|n| n.pressure)
            .chain(tangential.iter().copied())
            .map(|v| v / sy),
    );
    let any_inactive = curves.iter().any(|c| !c.inactive.is_empty());
    let note =
        (left_out > 0).then(|| format!("{left_out} node(s) with a non-finite value left out"));
    let frictional = curves.iter().filter(|c| c.friction.is_some()).count();
    let any_slip = curves
        .iter()
        .filter_map(|c| c.friction.as_ref())
        .any(|f| !f.slip_zones.is_empty());
    let rows = curves.len()
        + usize::from(any_inactive)
        + usize::from(note.is_some())
        + if frictional > 0 { frictional + 1 } else { 0 }
        + usize::from(any_slip);

    let what = if frictional > 0 {
        "contact pressure and friction"
    } else {
        "contact pressure"
    };
    let heading = if title.is_empty() {
        format!("{what} along the slave interface")
    } else {
        format!("{what}: {}", xml_sanitize(title))
    };
    let (heading, heading_font) = fit_heading(heading, SIZE.0);
    let x_desc = with_scale("s: arc length along the slave interface", ex);
    let y_desc = with_scale(
        if frictional > 0 {
            "p = λ / weight; tangential traction q = λ_t / weight"
        } else {
            "contact pressure p = λ / weight"
        },
        ey,
    );

    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let area = root
            .titled(&heading, ("sans-serif", heading_font).into_font())
            .map_err(plot_err)?;
        let builder = |xr: (f64, f64), yr: (f64, f64)| {
            let mut b = ChartBuilder::on(&area);
            b.margin(MARGIN)
                .margin_right(MARGIN + 12)
                .x_label_area_size(X_LABELS)
                .y_label_area_size(Y_LABELS);
            b.build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        };
        // Measure the plotting area (building draws nothing), then raise the top of the y range
        // so that the data stays below the legend box in the upper right corner.
        let (_, ph) = builder(xr, yr)
            .map_err(plot_err)?
            .plotting_area()
            .dim_in_pixel();
        let legend_h = ((rows as f64 * LEGEND_ROW + 24.0) / f64::from(ph.max(1))).min(0.6);
        let yr = (yr.0, yr.0 + (yr.1 - yr.0) / (1.0 - legend_h));
        let mut chart = builder(xr, yr).map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc(&x_desc)
            .y_desc(&y_desc)
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .bold_line_style(RGBColor(225, 225, 225))
            .light_line_style(TRANSPARENT)
            .draw()
            .map_err(plot_err)?;

        draw_friction(&mut chart, &curves, yr)?;
        draw_series(&mut chart, &curves, any_inactive, note.as_deref())?;
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        root.present().map_err(plot_err)?;
    }
    Ok(Some(buf))
}
