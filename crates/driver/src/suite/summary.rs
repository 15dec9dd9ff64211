//! Per-backend figures of a suite, as qpbenchmark (github.com/qpsolvers/qpbenchmark, read at
//! commit 1515983) reports a solver over a test set.
//!
//! * **The cases counted**: every case of the suite where backends run, a case that could not
//!   run at all (an unreadable scene or expectation, a refused mesh: [`CaseReport::error`])
//!   included — for every backend, as a failure at the time limit.  qpbenchmark counts every
//!   problem of its test set for every solver (`Results.build_success_rate_df` averages over
//!   all of a solver's rows), so a problem no solver could start is a failure of each, not a
//!   problem left out.  Cases without contact rows (one linear solve, `cholesky`, where no
//!   backend runs) are not counted.
//! * **Success rate**: the fraction of the counted cases a backend answered correctly
//!   ([`CaseRun::correct`]: verdict `pass` or `unexpected-pass` — `solved` with every figure
//!   within tolerance, or on a scene without a solution a non-solved status —; without an
//!   expectation, `solved`).  qpbenchmark's is `found` and the residuals within tolerance
//!   (`build_success_rate_df`); ours adds the expectation's figures.
//! * **Shifted geometric mean** of the solve time, `sgm(t) = exp(mean ln(tᵢ + s)) − s`
//!   (qpbenchmark's `shgeom.shgeom`), shift s = 10 ms.  A case the backend did not answer
//!   correctly counts at the time limit (qpbenchmark's `get_shgeom_for_metric_and_settings`
//!   with `not_found_values` = the runtime tolerance, i.e. the time limit: "we assume a
//!   solver's run time is at the time limit when it fails to solve a problem"), so failing
//!   fast does not look fast; without a time limit (only through the library: the command
//!   always has one), at the longest time any backend took on that case, or on any case for a
//!   case that could not run.  Deliberate difference: qpbenchmark's shift is 10 (seconds, its
//!   runtimes' unit); the suite's solves take milliseconds, where a 10 s shift would turn the
//!   mean into ≈ the arithmetic mean, dominated by the slowest cases (the outliers the shift is
//!   meant to temper), so the shift is 10 ms.
//! * The same of time ÷ floor with shift 1 (one floor): the machine's speed cancels.  A case
//!   that could not run has no floor, so it is left out of this mean only (for every backend
//!   alike, so it favours none).
//! * `sgm_time_relative`: each backend's time mean over the best backend's (1 for the best),
//!   as qpbenchmark reports its means (`means[solver] / best_mean`).

use super::report::{BackendSummary, CaseReport, CaseRun, Verdict};

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

/// The longest finite solve time of `runs` (0 when none).
fn longest<'a>(runs: impl Iterator<Item = &'a CaseRun>) -> f64 {
    runs.map(|r| r.solve_s)
        .filter(|t| t.is_finite())
        .fold(0.0, f64::max)
}

/// What one backend did on one counted case: `None` when the case does not count for it (no
/// contact row: no backend ran), else whether it answered correctly, its verdict (none for a
/// case that could not run) and the time it counts at.
fn outcome(backend: &str, case: &CaseReport, penalty: f64) -> Option<(bool, Option<Verdict>, f64)> {
    if case.error.is_some() {
        return Some((false, None, penalty));
    }
    let run = case.runs.iter().find(|r| r.backend == backend)?;
    let ok = run.correct() && run.solve_s.is_finite();
    Some((
        ok,
        Some(run.verdict),
        if ok { run.solve_s } else { penalty },
    ))
}

/// One summary per backend of `backends`, over `cases`; `time_limit_s` is the time a failure
/// counts at (see the module's docs).
pub fn summarise(
    backends: &[String],
    cases: &[CaseReport],
    time_limit_s: Option<f64>,
) -> Vec<BackendSummary> {
    let suite_longest = longest(cases.iter().flat_map(|c| &c.runs));
    let penalty = |case: &CaseReport| match time_limit_s {
        Some(t) => t,
        None if case.error.is_some() => suite_longest,
        None => longest(case.runs.iter()),
    };
    let mut out: Vec<BackendSummary> = backends
        .iter()
        .map(|backend| {
            let mut times = Vec::new();
            let mut ratios = Vec::new();
            let (mut n, mut correct, mut fail, mut xfail, mut xpass) = (0, 0, 0, 0, 0);
            for case in cases {
                let Some((ok, verdict, t)) = outcome(backend, case, penalty(case)) else {
                    continue;
                };
                n += 1;
                match verdict {
                    Some(Verdict::Fail) => fail += 1,
                    Some(Verdict::ExpectedFailure) => xfail += 1,
                    Some(Verdict::UnexpectedPass) => xpass += 1,
                    _ => {}
                }
                correct += usize::from(ok);
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
    use crate::suite::sample::{case, run, FLOOR_S};

    /// 2 cases × 2 backends, one case that could not run (qpbenchmark's rules, by hand).
    #[test]
    fn a_case_that_could_not_run_fails_every_backend_at_the_time_limit() {
        let backends = vec!["A".to_string(), "B".to_string()];
        let mut broken = case("broken", Vec::new());
        broken.error = Some("cannot read".into());
        broken.floor_s = f64::NAN;
        let cases = vec![
            case(
                "ok",
                vec![
                    run("A", "solved", 0.03, Verdict::Pass),
                    run("B", "inaccurate", 0.5, Verdict::Fail),
                ],
            ),
            broken,
        ];
        let s = summarise(&backends, &cases, Some(10.0));
        // Both cases count for both backends: A answered 1 of 2, B none.
        assert_eq!(
            (s[0].cases, s[0].correct, s[1].cases, s[1].correct),
            (2, 1, 2, 0)
        );
        assert_eq!((s[0].success_rate, s[1].success_rate), (0.5, 0.0));
        assert_eq!((s[0].regressions, s[1].regressions), (0, 1));
        // Times: A {0.03, 10 (broken, at the limit)}, B {10 (failed), 10 (broken)}, shift 0.01:
        // sgm_A = √(0.04 · 10.01) − 0.01, sgm_B = 10.01 − 0.01.
        let sgm_a = (0.04f64 * 10.01).sqrt() - 0.01;
        // A few ulps of exp(ln) and of the sums (values ≤ 10.01): 1e-13 relative is far below
        // any difference a wrong rule makes (dropping the broken case gives 0.03, not 0.62).
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-13 * y.abs();
        assert!(close(s[0].sgm_time_s, sgm_a), "{}", s[0].sgm_time_s);
        assert!(close(s[1].sgm_time_s, 10.0), "{}", s[1].sgm_time_s);
        assert!(close(s[0].sgm_time_relative, 1.0));
        assert!(close(s[1].sgm_time_relative, 10.0 / sgm_a));
        // Time ÷ floor only where there is a floor (case "ok"): A 3, B 10/0.01 = 1000.
        assert!(close(s[0].sgm_ratio, 0.03 / FLOOR_S), "{}", s[0].sgm_ratio);
        assert!(close(s[1].sgm_ratio, 10.0 / FLOOR_S), "{}", s[1].sgm_ratio);
        // Without a time limit a failure counts at the longest time on its case, and the
        // broken case (no time of its own) at the longest of the suite: 0.5 s, B's.
        let s = summarise(&backends, &cases, None);
        assert!(close(s[0].sgm_time_s, (0.04f64 * 0.51).sqrt() - 0.01));
        assert!(close(s[1].sgm_time_s, 0.5));
    }

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
