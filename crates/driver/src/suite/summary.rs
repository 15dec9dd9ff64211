//! Per-backend figures of a suite, as qpbenchmark reports a solver over a test set.
//!
//! * **Success rate**: the fraction of cases a backend answered correctly: verdict `pass` or
//!   `unexpected-pass` (`solved` with every figure within tolerance, or — on a scene without a
//!   solution — a non-solved status); an expected failure is no success; a case without
//!   expectation counts by its status alone.
//! * **Shifted geometric mean** of the solve time, `sgm(t) = exp(mean ln(tᵢ + s)) − s`, shift
//!   s = 10 ms: a geometric mean that small times cannot dominate.  A case the backend did not
//!   answer correctly counts at the time limit (qpbenchmark's rule; without a time limit, at
//!   the longest time any backend took on that case), so failing fast does not look fast.
//! * The same of time ÷ floor with shift 1 (one floor): the machine's speed cancels.
//! * `sgm_time_relative`: each backend's time mean over the best backend's (1 for the best).
//!
//! Cases without contact rows (one linear solve, no backend runs) are not counted.

use super::report::{BackendSummary, CaseReport, Verdict};

/// The time shift, seconds.
pub const TIME_SHIFT_S: f64 = 0.01;
/// The shift of time ÷ floor (one floor).
pub const RATIO_SHIFT: f64 = 1.0;

/// `exp(mean ln(xᵢ + shift)) − shift` (NaN for no value).
pub fn shifted_geometric_mean(values: &[f64], shift: f64) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    let mean = values.iter().map(|x| (x + shift).ln()).sum::<f64>() / values.len() as f64;
    mean.exp() - shift
}

/// One summary per backend of `backends`, over `cases`; `time_limit_s` is the penalty of a
/// failure (see the module's docs).
pub fn summarise(
    backends: &[String],
    cases: &[CaseReport],
    time_limit_s: Option<f64>,
) -> Vec<BackendSummary> {
    let mut out: Vec<BackendSummary> = backends
        .iter()
        .map(|backend| {
            let mut times = Vec::new();
            let mut ratios = Vec::new();
            let (mut n, mut correct, mut fail, mut xfail, mut xpass) = (0, 0, 0, 0, 0);
            for case in cases {
                let Some(run) = case.runs.iter().find(|r| &r.backend == backend) else {
                    continue;
                };
                n += 1;
                match run.verdict {
                    Verdict::Fail => fail += 1,
                    Verdict::ExpectedFailure => xfail += 1,
                    Verdict::UnexpectedPass => xpass += 1,
                    Verdict::Pass | Verdict::Unchecked => {}
                }
                let ok = run.correct();
                if ok {
                    correct += 1;
                }
                let penalty = time_limit_s.unwrap_or_else(|| {
                    case.runs
                        .iter()
                        .map(|r| r.solve_s)
                        .filter(|t| t.is_finite())
                        .fold(0.0, f64::max)
                });
                let spent = if run.solve_s.is_finite() {
                    run.solve_s
                } else {
                    0.0
                };
                let t = if ok { spent } else { penalty.max(spent) };
                times.push(t);
                if case.floor_s.is_finite() && case.floor_s > 0.0 {
                    ratios.push(t / case.floor_s);
                }
            }
            BackendSummary {
                backend: backend.clone(),
                cases: n,
                correct,
                success_rate: if n == 0 {
                    f64::NAN
                } else {
                    correct as f64 / n as f64
                },
                regressions: fail,
                expected_failures: xfail,
                unexpected_passes: xpass,
                sgm_time_s: shifted_geometric_mean(&times, TIME_SHIFT_S),
                sgm_ratio: shifted_geometric_mean(&ratios, RATIO_SHIFT),
                sgm_time_relative: f64::NAN,
            }
        })
        .collect();
    let best = out
        .iter()
        .map(|s| s.sgm_time_s)
        .filter(|t| t.is_finite())
        .fold(f64::INFINITY, f64::min);
    for s in &mut out {
        s.sgm_time_relative = s.sgm_time_s / best;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shifted_geometric_mean_by_hand() {
        // (0.01 + 0.01)·(0.09 + 0.01) = 0.002, √ = 0.04472…, minus the shift.
        let m = shifted_geometric_mean(&[0.01, 0.09], 0.01);
        assert!((m - (0.002f64.sqrt() - 0.01)).abs() < 1e-15, "{m}");
        // Equal values give themselves back; no value gives NaN.
        assert!((shifted_geometric_mean(&[3.0; 4], 1.0) - 3.0).abs() < 1e-14);
        assert!(shifted_geometric_mean(&[], 1.0).is_nan());
        // The shift tempers a tiny outlier: 1e-6 s beside 1 s is not a 1000× speed-up.
        let plain = (1e-6f64 * 1.0).sqrt();
        assert!(shifted_geometric_mean(&[1e-6, 1.0], TIME_SHIFT_S) > 50.0 * plain);
    }
}
