//! Layout shared by the charts drawn with plotters (the sweep's and the study's log–log figures,
//! pressure.svg), so that they look alike and a change of style is made once.

use plotters::style::RGBColor;

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
