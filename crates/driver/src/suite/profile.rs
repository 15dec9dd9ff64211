//! `suite.svg` of `signorini suite`: the performance profile of the backends over the suite
//! (Dolan & Moré, "Benchmarking optimization software with performance profiles", Math.
//! Program. 91, 2002).
//!
//! The profile's cases are the suite's cases where the backends run — the cases the summary
//! counts ([`crate::suite::summary`]) —: a case without contact rows (a single `cholesky` run)
//! is left out; a case that could not run at all
//! ([`CaseReport::error`](crate::suite::report::CaseReport::error)) is in, a failure of every
//! backend (as qpbenchmark counts every problem of its test set for every solver, a failure
//! at the time limit, never within any τ).  On a case, a backend's answer is
//! *correct* as the summary's success rate counts it ([`CaseRun::correct`]: verdict `pass` or
//! `unexpected-pass` — on a scene without solution, a refusal passes —, or `solved` without an
//! expectation), with a finite solve time.  Its
//! ratio is its time over the best correct time of any backend on that case (1 for the fastest;
//! a backend without a correct answer has none).  The profile of backend s is the step function
//!
//! ```text
//! ρ_s(τ) = |{cases whose ratio for s is ≤ τ}| / |cases|,   τ ≥ 1,
//! ```
//!
//! the fraction of the cases s answered correctly within τ times the best time: ρ_s(1) is the
//! fraction where s was fastest (ties count for each backend tied), ρ_s(τ → ∞) its success
//! rate.

use std::ops::Range;

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::report::{CaseReport, CaseRun, SuiteReport};
use crate::output::chart_style::{
    draw_legend, fit_heading, plot_err, LEGEND_ROW, MARGIN, X_LABELS, Y_LABELS,
};
use crate::output::svg::PALETTE;
use crate::output::{xml_sanitize, OutputError};

/// Canvas size in pixels (as the sweep's figures).
const SIZE: (u32, u32) = (900, 620);
/// The x axis reaches at least this τ.
const MIN_TAU: f64 = 10.0;
/// The x axis ends this factor beyond the largest ratio, so that the last step shows.
const TAU_ROOM: f64 = 1.25;

/// Whether a run is a correct answer with a usable time (see the module's docs).
fn correct(run: &CaseRun) -> bool {
    run.correct() && run.solve_s.is_finite() && run.solve_s >= 0.0
}

/// Whether the case belongs to the profile: it could not run (a failure of every backend), or
/// some backend of the suite ran on it.
fn profiled(case: &CaseReport, backends: &[String]) -> bool {
    case.error.is_some() || case.runs.iter().any(|r| backends.contains(&r.backend))
}

/// The number of profiled cases and, per backend of the report (in order), its ratios on the
/// cases it answered correctly (finite, ≥ 1), sorted.
fn ratios(report: &SuiteReport) -> (usize, Vec<(String, Vec<f64>)>) {
    let mut out: Vec<(String, Vec<f64>)> = report
        .backends
        .iter()
        .map(|b| (b.clone(), Vec::new()))
        .collect();
    let mut n = 0;
    for case in report
        .cases
        .iter()
        .filter(|c| profiled(c, &report.backends))
    {
        n += 1;
        let time = |b: &str| {
            case.runs
                .iter()
                .filter(|r| r.backend == b && correct(r))
                .map(|r| r.solve_s)
                .min_by(f64::total_cmp)
        };
        let Some(best) = report
            .backends
            .iter()
            .filter_map(|b| time(b))
            .min_by(f64::total_cmp)
        else {
            continue;
        };
        for (b, rs) in &mut out {
            if let Some(t) = time(b) {
                let r = if t <= best { 1.0 } else { t / best };
                // A best time of 0 beside a positive one: infinitely slower, never within τ.
                if r.is_finite() {
                    rs.push(r);
                }
            }
        }
    }
    for (_, rs) in &mut out {
        rs.sort_by(f64::total_cmp);
    }
    (n, out)
}

/// The performance profile: per backend of the report (in its order), the breakpoints
/// `(τ, ρ(τ))` of its step function (see the module's docs).  The first point is `(1, ρ(1))`;
/// each further point is a ratio `τ > 1` some case reached, with ρ from that τ on (ρ is
/// constant up to the next point, and from the last point to infinity).  A backend without a
/// correct answer has the single point `(1, 0)`.  Without any profiled case (every case has no
/// contact row) every list is empty.
pub fn profile(report: &SuiteReport) -> Vec<(String, Vec<(f64, f64)>)> {
    let (n, ratios) = ratios(report);
    ratios
        .into_iter()
        .map(|(backend, rs)| {
            if n == 0 {
                return (backend, Vec::new());
            }
            let rho = |k: usize| k as f64 / n as f64;
            let at_one = rs.iter().filter(|r| **r <= 1.0).count();
            let mut points = vec![(1.0, rho(at_one))];
            for (i, r) in rs.iter().enumerate().skip(at_one) {
                // Reached by the cases up to this one and those tied with it.
                let reached = i + 1;
                if rs.get(i + 1) == Some(r) {
                    continue;
                }
                points.push((*r, rho(reached)));
            }
            (backend, points)
        })
        .collect()
}

/// Tick positions on the τ axis `[1, hi]`: 1-2-5 multiples of powers of ten, or only the
/// powers of ten when that gives more than ten ticks.
fn tau_ticks(hi: f64) -> Vec<f64> {
    let last = hi.log10().ceil().max(1.0) as i32;
    let each = |mantissas: &[f64]| -> Vec<f64> {
        (0..=last)
            .flat_map(|e| mantissas.iter().map(move |m| m * 10f64.powi(e)))
            .filter(|v| *v <= hi)
            .collect()
    };
    let fine = each(&[1.0, 2.0, 5.0]);
    if fine.len() <= 10 {
        fine
    } else {
        each(&[1.0])
    }
}

/// The ρ axis: linear over its range (which reaches above 1 to make room for the legend), with
/// ticks at 0, 0.2, …, 1 only.
struct RhoAxis(RangedCoordf64);

impl Ranged for RhoAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.0.map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, _hint: Hint) -> Vec<f64> {
        (0..=5).map(|i| f64::from(i) / 5.0).collect()
    }

    fn range(&self) -> Range<f64> {
        self.0.range()
    }
}

/// Tick label of τ: an integer up to 10⁴, else `1e5` style.
fn tau_label(v: f64) -> String {
    if v < 1e4 + 0.5 {
        format!("{}", v.round())
    } else {
        format!("1e{}", v.log10().round())
    }
}

/// Renders `suite.svg`, the performance profile (see the module's docs): one step curve per
/// backend, τ on a logarithmic x axis from 1 to the largest ratio (with room, at least 10),
/// ρ on a linear y axis from 0 to 1.  The heading names the suite directory, the tolerance and
/// the number of cases; each backend's legend entry gives its success rate
/// (`clarabel: 3/4 correct (75 %)`).  Curves of backends earlier in the suite's order are drawn
/// wider, so that tied curves show each colour.  `None` when no backend answered any profiled
/// case correctly (nothing to draw).  Any text is allowed in names: characters XML forbids
/// become U+FFFD, plotters escapes the rest.
pub fn render_profile_svg(report: &SuiteReport) -> Result<Option<String>, OutputError> {
    let (n, ratios) = ratios(report);
    if ratios.iter().all(|(_, rs)| rs.is_empty()) {
        return Ok(None);
    }
    let largest = ratios
        .iter()
        .flat_map(|(_, rs)| rs.iter().copied())
        .fold(1.0, f64::max);
    let hi = (largest * TAU_ROOM).max(MIN_TAU);
    let curves = profile(report);
    let nb = curves.len();
    let labels: Vec<String> = ratios
        .iter()
        .map(|(b, rs)| {
            let k = rs.len();
            let pct = 100.0 * k as f64 / n as f64;
            xml_sanitize(&format!("{b}: {k}/{n} correct ({pct:.0} %)"))
        })
        .collect();
    let (heading, heading_font) = fit_heading(
        xml_sanitize(&format!(
            "performance profile: {} (tol {:e}, {n} case{})",
            report.dir,
            report.tolerance,
            if n == 1 { "" } else { "s" }
        )),
        SIZE.0,
    );

    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let area = root
            .titled(&heading, ("sans-serif", heading_font).into_font())
            .map_err(plot_err)?;
        let x_axis = || (1.0..hi).log_scale().with_key_points(tau_ticks(hi));
        let (y_lo, y_hi) = (-0.03, 1.03);
        let builder = |top: f64| {
            let mut b = ChartBuilder::on(&area);
            b.margin(MARGIN)
                .margin_right(MARGIN + 12)
                .x_label_area_size(X_LABELS)
                .y_label_area_size(Y_LABELS);
            b.build_cartesian_2d(x_axis(), RhoAxis((y_lo..top).into()))
        };
        // Measure the plotting area (building draws nothing), then raise the top of the y range
        // so that the legend box in the upper right corner stays above ρ = 1.
        let (_, ph) = builder(y_hi)
            .map_err(plot_err)?
            .plotting_area()
            .dim_in_pixel();
        let legend_h = ((nb as f64 * LEGEND_ROW + 24.0) / f64::from(ph.max(1))).min(0.6);
        let top = y_lo + (y_hi - y_lo) / (1.0 - legend_h);
        let mut chart = builder(top).map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc("τ: solve time ÷ the best correct time on the case")
            .y_desc("fraction of cases solved correctly within τ × best")
            .x_label_formatter(&|v| tau_label(*v))
            .y_label_formatter(&|v| format!("{v:.1}"))
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .bold_line_style(RGBColor(225, 225, 225))
            .light_line_style(TRANSPARENT)
            .draw()
            .map_err(plot_err)?;

        for (k, ((_, points), label)) in curves.iter().zip(&labels).enumerate() {
            let colour = PALETTE[k % PALETTE.len()];
            // Wider for earlier backends (2 px for the last, 2 px more per backend before it,
            // at most 10 px), so that a later curve on top of an earlier one leaves its edges.
            let width = (2 + 2 * (nb - 1 - k)).min(10) as u32;
            let mut step: Vec<(f64, f64)> = Vec::with_capacity(2 * points.len() + 1);
            for &(tau, rho) in points {
                if let Some(&(_, before)) = step.last() {
                    step.push((tau, before));
                }
                step.push((tau, rho));
            }
            if let Some(&(_, last)) = step.last() {
                step.push((hi, last));
            }
            let style = colour.stroke_width(width);
            let legend_style = colour.stroke_width(3);
            chart
                .draw_series(LineSeries::new(step, style))
                .map_err(plot_err)?
                .label(label.clone())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], legend_style));
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        root.present().map_err(plot_err)?;
    }
    Ok(Some(buf))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::suite::report::Verdict;
    use crate::suite::sample::{self, case, run};

    /// Backend C's name needs escaping in the SVG.
    const C: &str = "c<&>";

    /// Five profiled cases (a failure, a tie, an unexpected pass, a case nobody answers, a case
    /// that could not run) and one without contact rows (left out).
    fn report() -> SuiteReport {
        use Verdict::*;
        let mut broken = case("broken", Vec::new());
        broken.error = Some("cannot read".into());
        let mut free = case("free", vec![run("cholesky", "solved", 0.001, Pass)]);
        free.constraints = 0;
        let cases = vec![
            // best 1: A 1, B 2; C failed.
            case(
                "a",
                vec![
                    run("A", "solved", 1.0, Pass),
                    run("B", "solved", 2.0, Pass),
                    run(C, "solved", 0.5, Fail),
                ],
            ),
            // A and B tie at 3; C's faster answer is an expected failure (not correct).
            case(
                "b",
                vec![
                    run("A", "solved", 3.0, Pass),
                    run("B", "solved", 3.0, Pass),
                    run(C, "max-iterations", 1.5, ExpectedFailure),
                ],
            ),
            // best 2 (B): A 10 (an unexpected pass counts), C 5.
            case(
                "c",
                vec![
                    run("A", "solved", 10.0, UnexpectedPass),
                    run("B", "solved", 2.0, Pass),
                    run(C, "solved", 5.0, Pass),
                ],
            ),
            // Nobody correct: an expected failure, a wrong answer, a run that could not run.
            case(
                "d",
                vec![
                    run("A", "inaccurate", 1.0, ExpectedFailure),
                    run("B", "solved", 1.0, Fail),
                    run(C, "error", f64::NAN, Fail),
                ],
            ),
            broken,
            free,
        ];
        sample::report(
            "fixtures/seed",
            vec!["A".into(), "B".into(), C.into()],
            cases,
            None,
        )
    }

    #[test]
    fn the_profile_by_hand() {
        // By hand, over the 5 profiled cases a–d and broken (a failure of every backend;
        // free is left out):
        //   A: ratios a 1, b 1 (tie), c 10/2 = 5 → ρ(1) = 2/5, ρ(5) = 3/5;
        //   B: ratios a 2, b 1 (tie), c 1        → ρ(1) = 2/5, ρ(2) = 3/5;
        //   C: ratio c 5/2 = 2.5 only            → ρ(1) = 0,   ρ(2.5) = 1/5.
        let want: Vec<(String, Vec<(f64, f64)>)> = vec![
            ("A".into(), vec![(1.0, 2.0 / 5.0), (5.0, 3.0 / 5.0)]),
            ("B".into(), vec![(1.0, 2.0 / 5.0), (2.0, 3.0 / 5.0)]),
            (C.into(), vec![(1.0, 0.0), (2.5, 1.0 / 5.0)]),
        ];
        // Exact: the ratios are binary fractions and each ρ is the same one division k / 5.
        assert_eq!(profile(&report()), want);
        // ρ(τ → ∞) is the summary's success rate, the broken case counted alike.
        let r = report();
        for ((_, points), s) in profile(&r).iter().zip(&r.summary) {
            assert_eq!(points.last().map(|p| p.1), Some(s.success_rate));
        }
    }

    #[test]
    fn tied_ratios_make_one_step() {
        // Two cases where B takes exactly twice A's time: one step of 2/2 at τ = 2.
        let mut r = report();
        r.backends = vec!["A".into(), "B".into()];
        r.cases = vec![
            case(
                "x",
                vec![
                    run("A", "solved", 1.0, Verdict::Pass),
                    run("B", "solved", 2.0, Verdict::Pass),
                ],
            ),
            case(
                "y",
                vec![
                    run("A", "solved", 4.0, Verdict::Pass),
                    run("B", "solved", 8.0, Verdict::Pass),
                ],
            ),
        ];
        let p = profile(&r);
        assert_eq!(p[0].1, [(1.0, 1.0)]);
        assert_eq!(p[1].1, [(1.0, 0.0), (2.0, 1.0)]);
    }

    #[test]
    fn nothing_to_draw_without_a_correct_answer() {
        let mut r = report();
        r.cases
            .retain(|c| c.name == "d" || c.name == "broken" || c.name == "free");
        assert!(render_profile_svg(&r).unwrap().is_none());
        // A backend without correct answer: (1, 0), also when the only case could not run; no
        // profiled case at all (only a case without contact rows): empty lists.
        assert!(profile(&r).iter().all(|(_, p)| p == &[(1.0, 0.0)]));
        r.cases.retain(|c| c.name != "d");
        assert!(profile(&r).iter().all(|(_, p)| p == &[(1.0, 0.0)]));
        r.cases.retain(|c| c.name == "free");
        assert!(profile(&r).iter().all(|(_, p)| p.is_empty()));
        assert!(render_profile_svg(&r).unwrap().is_none());
    }

    #[test]
    fn the_svg_parses_and_has_each_legend() {
        let svg = render_profile_svg(&report()).unwrap().unwrap();
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let texts: Vec<String> = doc
            .descendants()
            .filter(|n| n.has_tag_name("text"))
            .map(|n| n.text().unwrap_or("").trim().to_string())
            .collect();
        // Success rates by hand: A and B 3 of 5 cases, C 1 of 5 (the broken case counts).
        for label in [
            "A: 3/5 correct (60 %)",
            "B: 3/5 correct (60 %)",
            "c<&>: 1/5 correct (20 %)",
        ] {
            assert!(texts.iter().any(|t| t == label), "{label} not in {texts:?}");
        }
        let heading = "performance profile: fixtures/seed (tol 1e-8, 5 cases)";
        assert!(texts.iter().any(|t| t == heading), "{texts:?}");
        // One polyline per backend: the steps of A end at (hi, 3/4) with hi = max(10, 1.25·5).
        let lines = doc
            .descendants()
            .filter(|n| n.has_tag_name("polyline"))
            .count();
        assert!(lines >= 3, "{lines}");
    }

    #[test]
    fn the_tau_axis_ticks() {
        assert_eq!(tau_ticks(10.0), [1.0, 2.0, 5.0, 10.0]);
        assert_eq!(tau_ticks(60.0), [1.0, 2.0, 5.0, 10.0, 20.0, 50.0]);
        assert_eq!(tau_ticks(2e5), [1.0, 10.0, 100.0, 1e3, 1e4, 1e5]);
        assert_eq!(tau_label(20.0), "20");
        assert_eq!(tau_label(1e5), "1e5");
    }
}
