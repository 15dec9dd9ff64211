//! A backend's answer against a scene's expectation: the [`Verdict`] and what broke.
//!
//! Each figure is compared as |measured − expected| ≤ rtol · scale, with a scale fixed by the
//! expectation or the problem's data (never by the measured value, so a wild answer cannot
//! loosen its own check):
//!
//! | figure | scale |
//! |---|---|
//! | objective | \|expected objective\| |
//! | largest displacement | expected largest displacement |
//! | a pair's normal force | max(\|expected force\|, Σ\|fᵢ\| the problem's load) |
//! | a probe (largest component) | max(\|expected probe\|, expected largest displacement) |
//!
//! A NaN anywhere fails its comparison.  A different number of pairs or probes, or other
//! names, is a failure of its own (the scene changed under its expectation).

use super::expectation::{Expectation, ExpectedStatus, Tolerances};
use super::report::{Figures, PairForce, ProbeValue, Verdict};

/// What a run ended with, as the check needs it.
#[derive(Debug, Clone, Copy)]
pub struct Answer<'a> {
    /// Backend name.
    pub backend: &'a str,
    /// Core-checked status.
    pub status: &'a str,
    /// The answer's figures (meaningful when `status` is `solved`).
    pub figures: &'a Figures,
}

/// `expected` and `measured` agree to `rtol` of `scale` (false when any is NaN).
fn close(measured: f64, expected: f64, rtol: f64, scale: f64) -> bool {
    (measured - expected).abs() <= rtol * scale
}

/// One failed comparison as a sentence: the figure, both values, the relative difference and
/// the tolerance.
fn mismatch(what: &str, measured: f64, expected: f64, rtol: f64, scale: f64) -> String {
    format!(
        "{what}: {measured:.9e}, expected {expected:.9e} (difference {:.1e} of the scale {scale:.3e}, rtol {rtol:.0e})",
        (measured - expected).abs() / scale
    )
}

/// Every figure of `measured` that is not within tolerance of `expected`, one sentence each;
/// `load` is the problem's Σ|fᵢ| (the floor of a pair force's scale).
pub fn compare_figures(
    expectation: &Expectation,
    expected: &Figures,
    measured: &Figures,
    load: f64,
) -> Vec<String> {
    let rtol = &expectation.rtol;
    let mut out = Vec::new();
    let scale = expected.objective.abs().max(f64::MIN_POSITIVE);
    if !close(
        measured.objective,
        expected.objective,
        rtol.objective(),
        scale,
    ) {
        out.push(mismatch(
            "objective",
            measured.objective,
            expected.objective,
            rtol.objective(),
            scale,
        ));
    }
    let umax = expected.max_displacement.max(f64::MIN_POSITIVE);
    if !close(
        measured.max_displacement,
        expected.max_displacement,
        rtol.max_displacement(),
        umax,
    ) {
        out.push(mismatch(
            "max |u|",
            measured.max_displacement,
            expected.max_displacement,
            rtol.max_displacement(),
            umax,
        ));
    }
    compare_forces(
        rtol,
        &expected.contact_forces,
        &measured.contact_forces,
        load,
        &mut out,
    );
    compare_probes(rtol, &expected.probes, &measured.probes, umax, &mut out);
    out
}

/// The pairs' normal forces of `measured` against `expected` (same pairs, each within its
/// tolerance of a scale at least `load`), one sentence per mismatch into `out`.
fn compare_forces(
    rtol: &Tolerances,
    expected: &[PairForce],
    measured: &[PairForce],
    load: f64,
    out: &mut Vec<String>,
) {
    if measured.len() != expected.len() {
        out.push(format!(
            "contact pairs: {}, expected {}",
            measured.len(),
            expected.len()
        ));
    } else {
        for (i, (m, e)) in measured.iter().zip(expected).enumerate() {
            let pair = format!("pair {} ({}–{})", i + 1, e.bodies[0], e.bodies[1]);
            if m.bodies != e.bodies {
                out.push(format!(
                    "pair {} bodies: {}–{}, expected {}–{}",
                    i + 1,
                    m.bodies[0],
                    m.bodies[1],
                    e.bodies[0],
                    e.bodies[1]
                ));
                continue;
            }
            let scale = e.normal_force.abs().max(load).max(f64::MIN_POSITIVE);
            let t = rtol.contact_force();
            if !close(m.normal_force, e.normal_force, t, scale) {
                out.push(mismatch(
                    &format!("{pair} normal force"),
                    m.normal_force,
                    e.normal_force,
                    t,
                    scale,
                ));
            }
            compare_tangential(&pair, m, e, t, scale, out);
        }
    }
}

/// A frictional pair's tangential force, when the expectation records one (an expectation
/// blessed before tangential forces were recorded checks none), on the scale of the pair's
/// forces: max(`scale`, |expected tangential force|).
fn compare_tangential(
    pair: &str,
    m: &PairForce,
    e: &PairForce,
    rtol: f64,
    scale: f64,
    out: &mut Vec<String>,
) {
    let Some(expected) = e.tangential_force else {
        return;
    };
    let what = format!("{pair} tangential force");
    let Some(measured) = m.tangential_force else {
        out.push(format!(
            "{what}: none (a frictionless pair), expected {expected:.9e}"
        ));
        return;
    };
    let scale = scale.max(expected.abs());
    if !close(measured, expected, rtol, scale) {
        out.push(mismatch(&what, measured, expected, rtol, scale));
    }
}

/// The probes' displacements of `measured` against `expected` (same probes, each component
/// within its tolerance of a scale at least `umax`), one sentence per mismatch into `out`.
fn compare_probes(
    rtol: &Tolerances,
    expected: &[ProbeValue],
    measured: &[ProbeValue],
    umax: f64,
    out: &mut Vec<String>,
) {
    if measured.len() != expected.len() {
        out.push(format!(
            "probes: {}, expected {}",
            measured.len(),
            expected.len()
        ));
    } else {
        for (m, e) in measured.iter().zip(expected) {
            if m.name != e.name {
                out.push(format!(
                    "probe names: \"{}\", expected \"{}\"",
                    m.name, e.name
                ));
                continue;
            }
            let magnitude = e.displacement[0].hypot(e.displacement[1]);
            let scale = magnitude.max(umax);
            let t = rtol.probe();
            for (c, axis) in ["ux", "uy"].iter().enumerate() {
                if !close(m.displacement[c], e.displacement[c], t, scale) {
                    out.push(mismatch(
                        &format!("probe \"{}\" {axis}", e.name),
                        m.displacement[c],
                        e.displacement[c],
                        t,
                        scale,
                    ));
                }
            }
        }
    }
}

/// The verdict of `answer` under `expectation` (`None`: no expectation file, so
/// [`Verdict::Unchecked`]) and its notes; `load` is the problem's Σ|fᵢ|.
pub fn check(
    expectation: Option<&Expectation>,
    answer: Answer<'_>,
    load: f64,
) -> (Verdict, Vec<String>) {
    let Some(expectation) = expectation else {
        return (Verdict::Unchecked, Vec::new());
    };
    let solved = answer.status == "solved";
    let expected = match (expectation.status, &expectation.figures) {
        (ExpectedStatus::NotSolved, _) => {
            return if solved {
                (
                    Verdict::Fail,
                    vec![
                        "solved, but the scene is expected to have no solution (no backend solved it when blessed)"
                            .to_string(),
                    ],
                )
            } else {
                (Verdict::Pass, Vec::new())
            };
        }
        (ExpectedStatus::Solved, Some(figures)) => figures,
        // `Expectation::read` refuses this; a hand-built one gets an honest failure.
        (ExpectedStatus::Solved, None) => {
            return (
                Verdict::Fail,
                vec!["the expectation says solved but holds no figures".to_string()],
            )
        }
    };
    let known_failure = expectation.expected_failures.get(answer.backend);
    if !solved {
        return match known_failure {
            Some(f) => {
                let mut notes = Vec::new();
                if let Some(before) = f.status.as_deref().filter(|s| *s != answer.status) {
                    notes.push(format!(
                        "expected to fail; ended {}, blessed as {before}",
                        answer.status
                    ));
                }
                (Verdict::ExpectedFailure, notes)
            }
            None => (
                Verdict::Fail,
                vec![format!("status: {}, expected solved", answer.status)],
            ),
        };
    }
    let broke = compare_figures(expectation, expected, answer.figures, load);
    if !broke.is_empty() {
        // `solved` with a wrong answer is a regression even for a backend expected to fail.
        return (Verdict::Fail, broke);
    }
    match known_failure {
        Some(f) => {
            let why = f
                .why
                .as_deref()
                .map(|w| format!(": {w}"))
                .unwrap_or_default();
            (
                Verdict::UnexpectedPass,
                vec![format!(
                    "solved within tolerance though expected to fail{why} (refresh with --bless)"
                )],
            )
        }
        None => (Verdict::Pass, Vec::new()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::suite::expectation::{ExpectedFailure, Tolerances};
    use crate::suite::report::{PairForce, ProbeValue};

    fn figures() -> Figures {
        Figures {
            objective: -2.0,
            max_displacement: 0.1,
            contact_forces: vec![PairForce {
                bodies: ["a".into(), "b".into()],
                normal_force: 5.0,
                tangential_force: None,
            }],
            probes: vec![ProbeValue {
                name: "tip".into(),
                displacement: [0.01, -0.05],
            }],
        }
    }

    fn expectation() -> Expectation {
        Expectation {
            scene: "t".into(),
            status: ExpectedStatus::Solved,
            figures: Some(figures()),
            rtol: Tolerances::default(),
            expected_failures: [(
                "osqp".to_string(),
                ExpectedFailure {
                    status: Some("inaccurate".into()),
                    why: Some("ADMM".into()),
                },
            )]
            .into(),
            blessed: None,
        }
    }

    fn verdict(backend: &str, status: &str, f: &Figures) -> (Verdict, Vec<String>) {
        let e = expectation();
        check(
            Some(&e),
            Answer {
                backend,
                status,
                figures: f,
            },
            10.0,
        )
    }

    #[test]
    fn the_same_figures_pass_and_each_figure_can_fail_alone() {
        assert_eq!(verdict("clarabel", "solved", &figures()).0, Verdict::Pass);
        // Just inside and just outside rtol = 1e-6 of each scale.
        let mut f = figures();
        f.objective = -2.0 * (1.0 + 0.9e-6);
        assert_eq!(verdict("clarabel", "solved", &f).0, Verdict::Pass);
        f.objective = -2.0 * (1.0 + 1.1e-6);
        let (v, notes) = verdict("clarabel", "solved", &f);
        assert_eq!(v, Verdict::Fail);
        assert!(notes[0].starts_with("objective"), "{notes:?}");
        let mut f = figures();
        f.max_displacement = 0.1 + 2e-7;
        assert!(verdict("clarabel", "solved", &f).1[0].starts_with("max |u|"));
        // The pair force's scale is the load 10 (> 5): 5e-6 off passes, 2e-5 fails.
        let mut f = figures();
        f.contact_forces[0].normal_force = 5.0 + 5e-6;
        assert_eq!(verdict("clarabel", "solved", &f).0, Verdict::Pass);
        f.contact_forces[0].normal_force = 5.0 + 2e-5;
        assert!(verdict("clarabel", "solved", &f).1[0].contains("pair 1 (a–b)"));
        // A probe's scale is max(|probe|, max |u|) = 0.1.
        let mut f = figures();
        f.probes[0].displacement[0] += 2e-7;
        assert!(verdict("clarabel", "solved", &f).1[0].contains("probe \"tip\" ux"));
        let mut f = figures();
        f.objective = f64::NAN;
        assert_eq!(verdict("clarabel", "solved", &f).0, Verdict::Fail);
    }

    #[test]
    fn a_recorded_tangential_force_is_checked_on_the_pair_s_scale() {
        // Expected 1.5 on a pair of normal force 5 under a load of 10: the scale is 10, so
        // 5e-6 off passes and 2e-5 fails (as the normal force), naming the figure.
        let mut e = expectation();
        if let Some(f) = e.figures.as_mut() {
            f.contact_forces[0].tangential_force = Some(1.5);
        }
        let run = |t: Option<f64>| {
            let mut f = figures();
            f.contact_forces[0].tangential_force = t;
            let answer = Answer {
                backend: "clarabel",
                status: "solved",
                figures: &f,
            };
            check(Some(&e), answer, 10.0)
        };
        assert_eq!(run(Some(1.5 + 5e-6)).0, Verdict::Pass);
        let (v, notes) = run(Some(1.5 + 2e-5));
        assert_eq!(v, Verdict::Fail);
        assert!(
            notes[0].starts_with("pair 1 (a–b) tangential force"),
            "{notes:?}"
        );
        let (v, notes) = run(None);
        assert_eq!(v, Verdict::Fail);
        assert!(notes[0].contains("none (a frictionless pair)"), "{notes:?}");
        // An expectation without one checks none: the old expectations still pass.
        assert_eq!(
            verdict("clarabel", "solved", &{
                let mut f = figures();
                f.contact_forces[0].tangential_force = Some(99.0);
                f
            })
            .0,
            Verdict::Pass
        );
    }

    #[test]
    fn changed_structure_fails_by_name() {
        let mut f = figures();
        f.contact_forces.clear();
        assert!(verdict("x", "solved", &f).1[0].contains("contact pairs: 0, expected 1"));
        let mut f = figures();
        f.probes[0].name = "other".into();
        assert!(
            verdict("x", "solved", &f).1[0].contains("probe names: \"other\", expected \"tip\"")
        );
    }

    #[test]
    fn expected_failures_unexpected_passes_and_wrong_answers() {
        let f = figures();
        assert_eq!(
            verdict("osqp", "inaccurate", &f),
            (Verdict::ExpectedFailure, vec![])
        );
        let (v, notes) = verdict("osqp", "max-iterations", &f);
        assert_eq!(v, Verdict::ExpectedFailure);
        assert!(notes[0].contains("blessed as inaccurate"));
        let (v, notes) = verdict("osqp", "solved", &f);
        assert_eq!(v, Verdict::UnexpectedPass);
        assert!(notes[0].contains("ADMM"));
        // Solved but wrong is a regression, expected failure or not.
        let mut wrong = figures();
        wrong.objective = -3.0;
        assert_eq!(verdict("osqp", "solved", &wrong).0, Verdict::Fail);
        let (v, notes) = verdict("clarabel", "time-limit", &f);
        assert_eq!(v, Verdict::Fail);
        assert_eq!(
            notes,
            vec!["status: time-limit, expected solved".to_string()]
        );
    }

    #[test]
    fn a_scene_without_solution_must_not_be_solved() {
        let e = Expectation {
            status: ExpectedStatus::NotSolved,
            figures: None,
            ..expectation()
        };
        let f = Figures::default();
        let answer = |status| Answer {
            backend: "clarabel",
            status,
            figures: &f,
        };
        assert_eq!(
            check(Some(&e), answer("dual-infeasible"), 1.0).0,
            Verdict::Pass
        );
        assert_eq!(check(Some(&e), answer("solved"), 1.0).0, Verdict::Fail);
        assert_eq!(check(None, answer("solved"), 1.0).0, Verdict::Unchecked);
    }
}
