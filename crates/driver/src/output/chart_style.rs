//! Layout shared by the charts drawn with plotters (the sweep's and the study's log–log figures,
//! pressure.svg), so that they look alike and a change of style is made once.

use plotters::coord::CoordTranslate;
use plotters::prelude::{ChartContext, DrawingBackend, SeriesLabelPosition};
use plotters::style::{Color, RGBColor, WHITE};

use crate::output::OutputError;

/// Margin around a chart, in pixels.
pub(crate) const MARGIN: u32 = 16;
/// Height of the x tick label area, in pixels.
pub(crate) const X_LABELS: u32 = 50;
/// Width of the y tick label area, in pixels.
pub(crate) const Y_LABELS: u32 = 80;
/// Legend font size in pixels.
pub(crate) const LEGEND_FONT: u32 = 15;
/// Height of one legend row in pixels (plotters' layout: font size + margins).
pub(crate) const LEGEND_ROW: f64 = 21.0;
/// Grey of legend entries that explain hollow markers, and of reference lines.
pub(crate) const GREY: RGBColor = RGBColor(120, 120, 120);

/// Largest heading font size in pixels.
pub(crate) const HEADING_FONT: u32 = 21;
/// Smallest heading font size in pixels (longer headings are cut).
pub(crate) const HEADING_FONT_MIN: u32 = 12;
/// Average glyph width of the sans-serif font, as a fraction of its size (a generous estimate).
const GLYPH_WIDTH: f64 = 0.5;

/// The heading and its font size, so that it fits a canvas `width` pixels wide: the largest
/// size up to [`HEADING_FONT`] at which it fits, else [`HEADING_FONT_MIN`] with the text cut and
/// ended by "…".
pub(crate) fn fit_heading(heading: String, width: u32) -> (String, u32) {
    let room = f64::from(width.saturating_sub(2 * MARGIN));
    let chars = heading.chars().count().max(1) as f64;
    let fits = (room / (GLYPH_WIDTH * chars)).floor();
    if fits >= f64::from(HEADING_FONT_MIN) {
        return (heading, (fits as u32).min(HEADING_FONT));
    }
    let keep = (room / (GLYPH_WIDTH * f64::from(HEADING_FONT_MIN))) as usize;
    let mut cut: String = heading.chars().take(keep.saturating_sub(1)).collect();
    cut.push('…');
    (cut, HEADING_FONT_MIN)
}

/// A plotting error as [`OutputError::Plot`].
pub(crate) fn plot_err<E: std::fmt::Debug>(e: E) -> OutputError {
    OutputError::Plot(format!("{e:?}"))
}

/// Draws the chart's legend (its series' labels) in the shared style at `position`.
pub(crate) fn draw_legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Result<(), OutputError> {
    chart
        .configure_series_labels()
        .position(position)
        .margin(10)
        .label_font(("sans-serif", LEGEND_FONT))
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(160, 160, 160))
        .draw()
        .map_err(plot_err)
}
