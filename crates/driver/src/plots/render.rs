//! Drawing of one log–log figure into an SVG string with plotters.

use crate::output::chart_style::{
    draw_legend, plot_err, GREY, LEGEND_FONT, LEGEND_ROW, MARGIN, X_LABELS, Y_LABELS,
};
use crate::output::svg::PALETTE;
use plotters::coord::combinators::WithKeyPoints;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use crate::output::{xml_sanitize, OutputError};

/// Canvas size in pixels.
const SIZE: (u32, u32) = (900, 620);
/// Marker radius in pixels.
const MARKER: i32 = 5;
/// Number of marker shapes (circle, square, triangle up, diamond, triangle down).
const SHAPES: usize = 5;

/// One series of a figure.
#[derive(Debug, Clone)]
pub(crate) struct Curve {
    /// Legend text.
    pub label: String,
    /// Line and marker colour.
    pub colour: RGBColor,
    /// Marker shape index (`None`: a plain line without markers).
    pub shape: Option<usize>,
    /// Dashed line (the floor).
    pub dashed: bool,
    /// Points joined by the line (solved rows), in drawing order.
    pub line: Vec<(f64, f64)>,
    /// Points drawn as hollow markers only (rows not solved).
    pub hollow: Vec<(f64, f64)>,
    /// A reference curve: its points alone do not make a figure worth writing.
    pub reference: bool,
}

impl Curve {
    /// The (empty) curve of the `k`-th backend: its colour and marker shape.
    pub fn backend(k: usize, label: String) -> Self {
        Self {
            label,
            colour: PALETTE[k % PALETTE.len()],
            shape: Some(k % SHAPES),
            dashed: false,
            line: Vec::new(),
            hollow: Vec::new(),
            reference: false,
        }
    }

    /// The dashed black floor curve.
    pub fn floor(label: String, line: Vec<(f64, f64)>) -> Self {
        Self {
            label,
            colour: BLACK,
            shape: None,
            dashed: true,
            line,
            hollow: Vec::new(),
            reference: true,
        }
    }

    /// Whether the curve has any point.
    fn is_empty(&self) -> bool {
        self.line.is_empty() && self.hollow.is_empty()
    }
}

/// A log–log figure.
#[derive(Debug, Clone)]
pub(crate) struct Figure {
    /// Heading above the chart.
    pub heading: String,
    /// x axis description (with unit).
    pub x_desc: String,
    /// y axis description (with unit).
    pub y_desc: String,
    /// The series (only positive finite points).
    pub curves: Vec<Curve>,
    /// A horizontal dashed grey line at this y, with its legend text.
    pub hline: Option<(f64, String)>,
    /// Extra legend lines without a glyph (e.g. how zero errors are drawn).
    pub notes: Vec<String>,
}

/// The figure with every text [`xml_sanitize`]d: plotters escapes `& < > " '` itself but
/// passes characters XML forbids (control characters) through, which would make the SVG
/// ill-formed.
fn sanitized(fig: &Figure) -> Figure {
    let mut fig = fig.clone();
    for text in [&mut fig.heading, &mut fig.x_desc, &mut fig.y_desc]
        .into_iter()
        .chain(fig.curves.iter_mut().map(|c| &mut c.label))
        .chain(fig.hline.iter_mut().map(|h| &mut h.1))
        .chain(fig.notes.iter_mut())
    {
        *text = xml_sanitize(text);
    }
    fig
}

/// Renders the figure; `None` when no backend curve has a point.  Any text is allowed (see
/// [`sanitized`]).
pub(crate) fn render(fig: &Figure) -> Result<Option<String>, OutputError> {
    let fig = &sanitized(fig);
    if fig.curves.iter().all(|c| c.reference || c.is_empty()) {
        return Ok(None);
    }
    let pts = || {
        fig.curves
            .iter()
            .flat_map(|c| c.line.iter().chain(&c.hollow))
            .copied()
    };
    let Some(xr) = span(pts().map(|p| p.0)) else {
        return Ok(None);
    };
    let Some(yr) = span(pts().map(|p| p.1).chain(fig.hline.as_ref().map(|h| h.0))) else {
        return Ok(None);
    };
    let xr = pad(xr, 0.06, 0.06);
    let yr = pad(yr, 0.08, 0.08);

    let shown: Vec<&Curve> = fig.curves.iter().filter(|c| !c.is_empty()).collect();
    let any_hollow = shown.iter().any(|c| !c.hollow.is_empty());
    let labels: Vec<&str> = shown
        .iter()
        .map(|c| c.label.as_str())
        .chain(fig.hline.as_ref().map(|h| h.1.as_str()))
        .chain(any_hollow.then_some(HOLLOW_LABEL))
        .chain(fig.notes.iter().map(String::as_str))
        .collect();

    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let area = root
            .titled(&fig.heading, ("sans-serif", 21).into_font())
            .map_err(plot_err)?;
        let builder = |xr: (f64, f64), yr: (f64, f64)| {
            let mut b = ChartBuilder::on(&area);
            b.margin(MARGIN)
                .margin_right(MARGIN + 12)
                .x_label_area_size(X_LABELS)
                .y_label_area_size(Y_LABELS);
            b.build_cartesian_2d(log_axis(xr), log_axis(yr))
        };
        // Measure the plotting area (building draws nothing), then place the legend.
        let (pw, ph) = builder(xr, yr)
            .map_err(plot_err)?
            .plotting_area()
            .dim_in_pixel();
        let (legend_w, legend_h) = legend_size(&labels, pw, ph);
        let (corner, yr) = place_legend(&shown, fig.hline.as_ref().map(|h| h.0), xr, yr, {
            (legend_w + 0.02, legend_h + 0.02)
        });
        let mut chart = builder(xr, yr).map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc(&fig.x_desc)
            .y_desc(&fig.y_desc)
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| tick_label(*v))
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .bold_line_style(RGBColor(225, 225, 225))
            .light_line_style(TRANSPARENT)
            .draw()
            .map_err(plot_err)?;

        draw_series(&mut chart, fig, &shown, any_hollow, xr)?;
        draw_legend(&mut chart, corner)?;
        root.present().map_err(plot_err)?;
    }
    Ok(Some(buf))
}

/// The legend's width and height as fractions of the plotting area (`pw` × `ph` pixels), for
/// `labels` in the legend font.
fn legend_size(labels: &[&str], pw: u32, ph: u32) -> (f64, f64) {
    let legend_w = (labels.iter().map(|l| l.chars().count()).max().unwrap_or(0) as f64
        * 0.56
        * f64::from(LEGEND_FONT)
        + 45.0)
        / f64::from(pw.max(1));
    let legend_h = (labels.len() as f64 * LEGEND_ROW + 12.0) / f64::from(ph.max(1));
    (legend_w, legend_h)
}

/// Draws the figure's reference line (dashed, across `xr`), its curves, and the legend entries
/// of the hollow markers (when some are shown) and of the notes.
fn draw_series<'a>(
    chart: &mut Chart<'a, 'a>,
    fig: &Figure,
    shown: &[&Curve],
    any_hollow: bool,
    xr: (f64, f64),
) -> Result<(), OutputError> {
    if let Some((y, label)) = &fig.hline {
        let style = GREY.stroke_width(2);
        chart
            .draw_series(DashedLineSeries::new([(xr.0, *y), (xr.1, *y)], 8, 5, style))
            .map_err(plot_err)?
            .label(label.clone())
            .legend(move |(x, y)| DashedPathElement::new([(x, y), (x + 24, y)], 6, 4, style));
    }
    for c in shown {
        draw_curve(chart, c)?;
    }
    if any_hollow {
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
            .map_err(plot_err)?
            .label(HOLLOW_LABEL)
            .legend(|(x, y)| {
                EmptyElement::at((x + 12, y))
                    + PathElement::new(closed_outline(0), GREY.stroke_width(2))
            });
    }
    for note in &fig.notes {
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
            .map_err(plot_err)?
            .label(note.clone())
            .legend(|(x, y)| EmptyElement::at((x, y)));
    }
    Ok(())
}

/// Legend text of the hollow-marker entry.
const HOLLOW_LABEL: &str = "hollow: not solved";

/// The chart type of every figure.
type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<WithKeyPoints<LogCoord<f64>>, WithKeyPoints<LogCoord<f64>>>,
>;

/// Draws one curve: line (dashed or solid), filled markers on it, hollow markers off it.
fn draw_curve<'a>(chart: &mut Chart<'a, 'a>, c: &Curve) -> Result<(), OutputError> {
    let colour = c.colour;
    let style = colour.stroke_width(2);
    let label = c.label.clone();
    match (c.dashed, c.shape) {
        (true, _) => {
            chart
                .draw_series(DashedLineSeries::new(c.line.clone(), 8, 5, style))
                .map_err(plot_err)?
                .label(label)
                .legend(move |(x, y)| DashedPathElement::new([(x, y), (x + 24, y)], 6, 4, style));
        }
        (false, None) => {
            chart
                .draw_series(LineSeries::new(c.line.clone(), style))
                .map_err(plot_err)?
                .label(label)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], style));
        }
        (false, Some(shape)) => {
            chart
                .draw_series(LineSeries::new(c.line.clone(), style))
                .map_err(plot_err)?
                .label(label)
                .legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new([(0, 0), (24, 0)], style)
                        + Polygon::new(
                            marker_outline(shape)
                                .into_iter()
                                .map(|(u, v)| (u + 12, v))
                                .collect::<Vec<_>>(),
                            colour.filled(),
                        )
                });
        }
    }
    if let Some(shape) = c.shape {
        chart
            .draw_series(c.line.iter().map(|&p| {
                EmptyElement::at(p) + Polygon::new(marker_outline(shape), colour.filled())
            }))
            .map_err(plot_err)?;
        chart
            .draw_series(c.hollow.iter().map(|&p| {
                EmptyElement::at(p)
                    + PathElement::new(closed_outline(shape), colour.stroke_width(2))
            }))
            .map_err(plot_err)?;
    }
    Ok(())
}

/// Closed outline of a marker (for drawing it hollow).
fn closed_outline(shape: usize) -> Vec<(i32, i32)> {
    let mut v = marker_outline(shape);
    if let Some(&first) = v.first() {
        v.push(first);
    }
    v
}

/// Pixel outline of a marker around (0, 0): circle (12-gon), square, triangle up, diamond,
/// triangle down.
fn marker_outline(shape: usize) -> Vec<(i32, i32)> {
    let r = MARKER;
    match shape % SHAPES {
        0 => (0..12)
            .map(|i| {
                let a = f64::from(i) * std::f64::consts::PI / 6.0;
                let r = f64::from(r);
                ((r * a.cos()).round() as i32, (r * a.sin()).round() as i32)
            })
            .collect(),
        1 => vec![
            (-r + 1, -r + 1),
            (r - 1, -r + 1),
            (r - 1, r - 1),
            (-r + 1, r - 1),
        ],
        2 => vec![(0, -r - 1), (r + 1, r - 1), (-r - 1, r - 1)],
        3 => vec![(0, -r - 1), (r + 1, 0), (0, r + 1), (-r - 1, 0)],
        _ => vec![(0, r + 1), (r + 1, -r + 1), (-r - 1, -r + 1)],
    }
}

/// Smallest and largest positive finite value, if any.
fn span(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((f64::min(lo, v), f64::max(hi, v))),
        })
}

/// Widens a positive range in log space: at least a factor 4 wide, then by `lo`/`hi` of its
/// log width on each side.
fn pad((a, b): (f64, f64), lo: f64, hi: f64) -> (f64, f64) {
    let (mut la, mut lb) = (a.log10(), b.log10());
    let min_width = 4f64.log10();
    if lb - la < min_width {
        let mid = 0.5 * (la + lb);
        la = mid - 0.5 * min_width;
        lb = mid + 0.5 * min_width;
    }
    let w = lb - la;
    (10f64.powf(la - lo * w), 10f64.powf(lb + hi * w))
}

/// A logarithmic axis over `r` with readable tick positions: the powers of ten inside, or
/// 1-2-5 (or 1…9) multiples of them when fewer than three powers fit.
fn log_axis(r: (f64, f64)) -> WithKeyPoints<LogCoord<f64>> {
    (r.0..r.1).log_scale().with_key_points(ticks(r))
}

/// Tick positions for a logarithmic axis over `r` (see [`log_axis`]).
fn ticks((lo, hi): (f64, f64)) -> Vec<f64> {
    let first = lo.log10().floor() as i32;
    let last = hi.log10().ceil() as i32;
    for mantissas in [
        &[1.0][..],
        &[1.0, 2.0, 5.0],
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0],
    ] {
        let t: Vec<f64> = (first..=last)
            .flat_map(|e| mantissas.iter().map(move |m| clean(m * 10f64.powi(e))))
            .filter(|v| *v >= lo && *v <= hi)
            .collect();
        if t.len() >= 3 || mantissas.len() == 9 {
            return t;
        }
    }
    Vec::new()
}

/// Rounds to 12 significant digits (so 3 × 10⁻⁴ prints as 0.0003, not 0.00030000000000000003).
fn clean(v: f64) -> f64 {
    format!("{v:.11e}").parse().unwrap_or(v)
}

/// Tick label: plain decimals from 0.001 to 99999, else `2e-6` style.
fn tick_label(v: f64) -> String {
    if !v.is_finite() || v <= 0.0 {
        return format!("{v}");
    }
    let e = v.log10().floor() as i32;
    if (-3..=4).contains(&e) {
        let decimals = (2 - e).max(0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let m = clean(v / 10f64.powi(e));
        format!("{m}e{e}")
    }
}

/// Picks the legend corner overlapping the fewest data (points and samples along the lines, in
/// normalised log coordinates).  If every corner is occupied, the y range is stretched upward so
/// that the data clears an upper corner, and that corner is used.  `size` is the legend's
/// (width, height) as fractions of the plotting area.
fn place_legend(
    curves: &[&Curve],
    hline: Option<f64>,
    xr: (f64, f64),
    yr: (f64, f64),
    size: (f64, f64),
) -> (SeriesLabelPosition, (f64, f64)) {
    let norm = |v: f64, r: (f64, f64)| (v.ln() - r.0.ln()) / (r.1.ln() - r.0.ln());
    let mut samples: Vec<(f64, f64)> = Vec::new();
    for c in curves {
        for w in c.line.windows(2) {
            for i in 0..=16 {
                let t = f64::from(i) / 16.0;
                let x = w[0].0.ln() * (1.0 - t) + w[1].0.ln() * t;
                let y = w[0].1.ln() * (1.0 - t) + w[1].1.ln() * t;
                samples.push((x.exp(), y.exp()));
            }
        }
        samples.extend(c.line.iter().chain(&c.hollow));
    }
    if let Some(y) = hline {
        samples.extend((0..=16).map(|i| {
            let t = f64::from(i) / 16.0;
            ((xr.0.ln() * (1.0 - t) + xr.1.ln() * t).exp(), y)
        }));
    }
    let (w, h) = size;
    let count = |left: bool, top: bool, yr: (f64, f64)| {
        samples
            .iter()
            .filter(|(x, y)| {
                let (u, v) = (norm(*x, xr), norm(*y, yr));
                let in_x = if left { u <= w } else { u >= 1.0 - w };
                let in_y = if top { v >= 1.0 - h } else { v <= h };
                in_x && in_y
            })
            .count()
    };
    use SeriesLabelPosition::{LowerLeft, LowerRight, UpperLeft, UpperRight};
    let corners = [
        (UpperLeft, true, true),
        (UpperRight, false, true),
        (LowerRight, false, false),
        (LowerLeft, true, false),
    ];
    let counts: Vec<usize> = corners.iter().map(|c| count(c.1, c.2, yr)).collect();
    let best = (0..4).min_by_key(|&i| counts[i]).unwrap_or(0);
    if counts[best] == 0 || h >= 0.9 {
        let (pos, _, _) = corners
            .into_iter()
            .nth(best)
            .unwrap_or((UpperLeft, true, true));
        return (pos, yr);
    }
    // Stretch the top so that all data lies below the legend box.
    let (lo, hi) = (yr.0.ln(), yr.1.ln());
    let new_hi = lo + (hi - lo) / (1.0 - h);
    let yr = (yr.0, new_hi.exp());
    let pos = if count(true, true, yr) <= count(false, true, yr) {
        UpperLeft
    } else {
        UpperRight
    };
    (pos, yr)
}
