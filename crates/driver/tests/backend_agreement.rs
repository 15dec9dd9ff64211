//! Every seed fixture, meshed and assembled once, solved by every backend (clarabel, osqp,
//! dual-pgs, dual-uzawa and the dual-ssn reference) at a tight tolerance: all must report
//! `solved`, agree on the displacements to 1e-6 of the largest one and on the multipliers to 1e-6
//! of the force scale, and find the same active set.

// Helpers are test code too: a failed unwrap is a failed test.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use signorini::backends::{make_backend, BackendKind};
use signorini::run;
use signorini_core::mesh::MeshLimits;
use signorini_core::qp::{mat_vec, norm_inf, QpBackend, QpStatus, SolveOptions};
use signorini_core::report::is_active;
use signorini_core::solve::{solve_model, Solution};

/// KKT tolerance (measured: every backend meets it on every seed fixture).
const TOL: f64 = 1e-10;
/// Agreement required between any two backends, relative to max |u| (resp. the force scale).
/// Independent reference: the QP is strictly convex on the free DOFs, so two answers that each
/// meet the KKT conditions to TOL differ by at most about κ·TOL, κ the condition number of the
/// reduced stiffness (≤ 10⁴ on these meshes): 1e-6 covers that bound.
const AGREE: f64 = 1e-6;

/// Every backend of this build, each once, in [`BackendKind::ALL`] order: dual-ssn, the
/// reference of the active-set comparison below, comes last.
fn backends() -> Vec<Box<dyn QpBackend>> {
    let all: Vec<Box<dyn QpBackend>> = BackendKind::ALL
        .into_iter()
        .filter(|k| k.available())
        .map(|k| make_backend(k).unwrap())
        .collect();
    assert_eq!(all.last().unwrap().name(), "dual-ssn");
    all
}

fn seed_fixtures() -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/seed");
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

/// Problems found on one fixture (empty when all backends agree).
fn check_fixture(path: &Path) -> Vec<String> {
    let name = path.file_stem().unwrap().to_string_lossy().into_owned();
    let scene = run::load_scene(Some(path)).unwrap();
    let prepared = run::prepare(&scene, &MeshLimits::default()).unwrap();
    let model = &prepared.model;
    let qp = &prepared.qp;
    assert!(qp.rows() > 0, "{name}: no contact row");
    let options = SolveOptions {
        tol: TOL,
        ..SolveOptions::default()
    };
    let mut problems = Vec::new();
    let solutions: Vec<Solution> = backends()
        .into_iter()
        .map(|mut b| solve_model(model, qp, b.as_mut(), &options).unwrap())
        .collect();
    for s in &solutions {
        if s.status != QpStatus::Solved {
            problems.push(format!(
                "{name}/{}: status {} ({:?}, {:?})",
                s.backend, s.status, s.residuals, s.message
            ));
        }
        if !s
            .displacement
            .iter()
            .chain(&s.multipliers)
            .all(|v| v.is_finite())
        {
            problems.push(format!("{name}/{}: non-finite answer", s.backend));
        }
    }
    if !problems.is_empty() {
        return problems;
    }

    let u_scale = solutions
        .iter()
        .map(|s| norm_inf(&s.displacement))
        .fold(0.0, f64::max);
    // Force scale of `report::is_active`: the larger of the largest λ and Σ|applied load|.
    let force_scale = solutions
        .iter()
        .flat_map(|s| s.multipliers.iter().copied())
        .fold(model.load.iter().map(|f| f.abs()).sum(), f64::max);
    for (i, a) in solutions.iter().enumerate() {
        for b in &solutions[i + 1..] {
            let du = a
                .displacement
                .iter()
                .zip(&b.displacement)
                .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
            if du > AGREE * u_scale {
                problems.push(format!(
                    "{name}: {} vs {}: max |Δu| = {:.2e} of max |u|",
                    a.backend,
                    b.backend,
                    du / u_scale
                ));
            }
            let dl = a
                .multipliers
                .iter()
                .zip(&b.multipliers)
                .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
            if dl > AGREE * force_scale {
                problems.push(format!(
                    "{name}: {} vs {}: max |Δλ| = {:.2e} of the force scale",
                    a.backend,
                    b.backend,
                    dl / force_scale
                ));
            }
        }
    }

    // Active sets against the dual-ssn reference (exact once its set settles).  A row may
    // differ only if it is weakly active: λ below 1e-4 of the force scale in both answers AND a
    // final gap below 1e-8 of max |u| in both (measured: no seed fixture has such a row, every
    // set agrees exactly).
    let reference = solutions.last().unwrap();
    let gap_of = |s: &Solution| -> Vec<f64> {
        let bu = mat_vec(&model.constraints, &s.displacement);
        model.gap.iter().zip(bu).map(|(g, b)| g - b).collect()
    };
    let reference_gap = gap_of(reference);
    for s in &solutions[..solutions.len() - 1] {
        let gap = gap_of(s);
        for (row, (l, l_ref)) in s.multipliers.iter().zip(&reference.multipliers).enumerate() {
            if is_active(*l, force_scale) == is_active(*l_ref, force_scale) {
                continue;
            }
            let weak = l.max(*l_ref) < 1e-4 * force_scale
                && gap[row].abs().max(reference_gap[row].abs()) < 1e-8 * u_scale;
            if !weak {
                problems.push(format!(
                    "{name}: row {row} active in {} but not in {} (λ {l:.3e} vs {l_ref:.3e}, \
                     gap {:.3e} vs {:.3e})",
                    if is_active(*l, force_scale) {
                        s.backend.as_str()
                    } else {
                        reference.backend.as_str()
                    },
                    if is_active(*l, force_scale) {
                        reference.backend.as_str()
                    } else {
                        s.backend.as_str()
                    },
                    gap[row],
                    reference_gap[row]
                ));
            }
        }
    }
    problems
}

#[test]
fn every_backend_solves_every_seed_fixture_to_the_same_answer() {
    let files = seed_fixtures();
    assert!(files.len() >= 19, "seed fixtures: {}", files.len());
    let problems: Vec<String> = files.iter().flat_map(|f| check_fixture(f)).collect();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
