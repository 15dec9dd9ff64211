//! Where the time goes on the long-interface strip (run by hand, prints timings):
//!
//! ```text
//! cargo test -p signorini-scene-tests --release --test pdas_measure -- --ignored --nocapture
//! ```
//!
//! The strip of the issue (20 × 0.02 on a 20 × 0.04 foundation, hmax 0.01, floating in y or
//! clamped at its left end) is meshed and assembled here from an inline scene; each quantity is
//! the median of five runs in one process, after one warm-up, so that the ratios do not mix
//! cold and warm caches.  Printed: the floor, the AMD orderings of A and K, the analysis and
//! numeric LDLᵀ of K, faer's LLᵀ of A and our LDLᵀ of A alone (same pattern: the cost of LDLᵀ
//! over LLᵀ), nnz(L) of A and of K (the fill the contact coupling adds), one solve, and the
//! whole pdas solve.
#![allow(clippy::unwrap_used)]

mod common;

use std::time::{Duration, Instant};

use signorini_core::solve::floor_time;
use signorini_qp::linalg::fill_reducing_order;
use signorini_qp::{QpBackend, QpProblem, QpStatus, SolveOptions};

use signorini_pdas::internals::KktFactor;
use signorini_pdas::PdasBackend;

fn median(mut f: impl FnMut() -> Duration) -> f64 {
    f();
    let mut t: Vec<f64> = (0..5).map(|_| f().as_secs_f64() * 1e3).collect();
    t.sort_by(f64::total_cmp);
    t[2]
}

fn timed(f: impl FnOnce()) -> Duration {
    let clock = Instant::now();
    f();
    clock.elapsed()
}

#[test]
#[ignore = "measurement, run by hand"]
fn where_the_time_goes_on_the_strip() {
    for clamped in [false, true] {
        let p = common::strip_scaled(20.0, clamped, (0.0, 20.0));
        let floor = median(|| floor_time(&p).unwrap());
        let amd_a = median(|| timed(|| drop(fill_reducing_order(&p.stiffness).unwrap())));
        let pattern_k = signorini_qp::linalg::kkt::kkt_pattern(&p.stiffness, &p.constraints);
        let pattern_k = pattern_k.unwrap();
        let amd_k = median(|| timed(|| drop(fill_reducing_order(&pattern_k).unwrap())));
        let analyse = median(|| timed(|| drop(KktFactor::analyse(&p))));
        let (mut factor, kkt) = KktFactor::analyse(&p).unwrap();
        factor.allocate().unwrap();
        let numeric = median(|| timed(|| factor.factor(&kkt, 1e-13, 1e-10).unwrap()));
        let pattern = signorini_qp::linalg::CholeskyPattern::analyse(&p.stiffness);
        let llt_a = match &pattern {
            Ok(pattern) => median(|| timed(|| drop(pattern.factor(&p.stiffness)))),
            Err(_) => f64::NAN,
        };
        let a_only = QpProblem {
            constraints: sprs::CsMat::zero((0, p.dofs())).to_csc(),
            gap: Vec::new(),
            blocks: Vec::new(),
            ..p.clone()
        };
        let (mut factor_a, kkt_a) = KktFactor::analyse(&a_only).unwrap();
        factor_a.allocate().unwrap();
        let ldlt_a = median(|| timed(|| factor_a.factor(&kkt_a, 1e-13, 1e-10).unwrap()));
        println!(
            "nnz(L) of A {:.3e}, of K {:.3e}; LDLᵀ(A) {ldlt_a:.1} ms",
            factor_a.nnz_l() as f64,
            factor.nnz_l() as f64
        );
        let mut rhs = vec![1.0; kkt.dim()];
        let solve = median(|| timed(|| factor.solve_in_place(&mut rhs)));
        let mut status = QpStatus::NumericalError;
        let mut message = String::new();
        let pdas = median(|| {
            let clock = Instant::now();
            let s = PdasBackend::default()
                .solve(&p, &SolveOptions::default())
                .unwrap();
            let t = clock.elapsed();
            status = s.status;
            message = s.message.unwrap_or_default();
            t
        });
        println!(
            "strip {} ({} DOFs, {} rows): floor {floor:.1} ms; AMD(A) {amd_a:.1}, AMD(K) {amd_k:.1}, \
             analyse(K) {analyse:.1}, LDLᵀ(K) {numeric:.1}, LLᵀ(A) {llt_a:.1}, solve {solve:.2} ms; pdas {pdas:.1} ms = \
             {:.2}× floor, {status}: {message}",
            if clamped { "clamped" } else { "floating" },
            p.dofs(),
            p.rows(),
            pdas / floor
        );
    }
}

/// K's ordering from A's: AMD of A, each multiplier placed right after the last of its DOFs.
fn ordering_after_dofs(p: &QpProblem) -> signorini_qp::linalg::FillOrdering {
    ordering_after(p, &fill_reducing_order(&p.stiffness).unwrap())
}

/// K's ordering from the AMD of A + BᵀB (the pattern a penalty coupling would have), each
/// multiplier right after the last of its DOFs.
fn ordering_penalty(p: &QpProblem) -> signorini_qp::linalg::FillOrdering {
    let b = p.constraints.to_csc();
    let bt = b.transpose_view().to_csc();
    let btb = &bt * &b;
    let coupled = &p.stiffness + &btb;
    ordering_after(p, &fill_reducing_order(&coupled).unwrap())
}

/// Each multiplier placed right after the last of its DOFs in `a_order` (an ordering of n DOFs).
fn ordering_after(
    p: &QpProblem,
    a_order: &signorini_qp::linalg::FillOrdering,
) -> signorini_qp::linalg::FillOrdering {
    let n = p.dofs();
    let m = p.rows();
    let b = p.constraints.to_csr();
    let mut keys: Vec<(usize, usize)> = (0..n).map(|j| (2 * a_order.inverse[j], j)).collect();
    for (r, row) in b.outer_iterator().enumerate() {
        let last = row
            .iter()
            .map(|(j, _)| a_order.inverse[j])
            .max()
            .unwrap_or(n);
        keys.push((2 * last + 1, n + r));
    }
    keys.sort_unstable();
    let forward: Vec<usize> = keys.into_iter().map(|(_, i)| i).collect();
    debug_assert_eq!(forward.len(), n + m);
    signorini_qp::linalg::FillOrdering::from_forward(
        forward,
        signorini_qp::linalg::OrderingMethod::Amd,
    )
}

/// AMD of K's graph with the runs of identical neighbourhoods (a node's two DOFs) merged.
fn ordering_compressed(k: &signorini_qp::CscMatrix) -> signorini_qp::linalg::FillOrdering {
    let (xadj, adjncy) = signorini_qp::linalg::ordering::adjacency(k).unwrap();
    let g = signorini_qp::linalg::ordering::Compressed::of(&xadj, &adjncy);
    let groups = g.start.len() - 1;
    let mut indptr = vec![0];
    let mut indices = Vec::with_capacity(g.adjncy.len() + groups);
    for v in 0..groups {
        let mut list: Vec<usize> = g.adjncy[g.xadj[v]..g.xadj[v + 1]].to_vec();
        list.push(v);
        list.sort_unstable();
        indices.extend(list);
        indptr.push(indices.len());
    }
    let data = vec![1.0; indices.len()];
    let graph = sprs::CsMat::new_csc((groups, groups), indptr, indices, data);
    let order = fill_reducing_order(&graph).unwrap();
    let mut forward = Vec::with_capacity(k.rows());
    for &grp in &order.forward {
        forward.extend(g.start[grp]..g.start[grp + 1]);
    }
    signorini_qp::linalg::FillOrdering::from_forward(
        forward,
        signorini_qp::linalg::OrderingMethod::Amd,
    )
}

#[test]
#[ignore = "measurement, run by hand"]
fn kkt_orderings_on_the_tresca_strip() {
    use signorini_core::scene::Friction;
    use signorini_qp::linalg::{CholeskyPattern, Layout};
    for tresca in [false, true] {
        let mut scene = common::strip_scene(20.0, false, (0.0, 20.0));
        if tresca {
            scene.contacts[0].friction = Some(Friction::Tresca(1e-4));
        }
        let p = signorini_core::solve::ScaledQp::new(common::qp_of(&scene)).problem;
        // K's lower pattern as a CSC matrix (the values do not matter to an ordering).
        let k = &signorini_qp::linalg::kkt::kkt_pattern(&p.stiffness, &p.constraints).unwrap();
        let amd_a = median(|| timed(|| drop(fill_reducing_order(&p.stiffness).unwrap())));
        let amd_k = median(|| timed(|| drop(fill_reducing_order(k).unwrap())));
        let after = median(|| timed(|| drop(ordering_after_dofs(&p))));
        let nnz = |o: &signorini_qp::linalg::FillOrdering| {
            CholeskyPattern::analyse_laid_out(k, o, Layout::FaerChoice)
                .unwrap()
                .stored_values()
        };
        let exact = |o: &signorini_qp::linalg::FillOrdering| {
            signorini_qp::linalg::column_counts(k, &o.inverse)
                .unwrap()
                .iter()
                .sum::<usize>()
        };
        for _ in 0..3 {
            let compressed = median(|| timed(|| drop(ordering_compressed(k))));
            let plain = median(|| timed(|| drop(fill_reducing_order(k).unwrap())));
            println!("  compressed AMD of K {compressed:.1} ms, AMD of K {plain:.1} ms");
        }
        let o_c = ordering_compressed(k);
        println!(
            "  compressed: stored {:.3e} exact {:.3e}",
            nnz(&o_c) as f64,
            exact(&o_c) as f64
        );
        let penalty = median(|| timed(|| drop(ordering_penalty(&p))));
        let o_pen = ordering_penalty(&p);
        println!(
            "  penalty-graph ordering {penalty:.1} ms: stored {:.3e} exact {:.3e}",
            nnz(&o_pen) as f64,
            exact(&o_pen) as f64
        );
        let o_k = fill_reducing_order(k).unwrap();
        let o_after = ordering_after_dofs(&p);
        let a_pattern = CholeskyPattern::analyse_laid_out(
            &p.stiffness,
            &fill_reducing_order(&p.stiffness).unwrap(),
            Layout::FaerChoice,
        )
        .unwrap();
        println!(
            "tresca {tresca}: n {} m {}; AMD(A) {amd_a:.1} ms, AMD(K) {amd_k:.1} ms, after-DOFs {after:.1} ms; \
             nnz(L_A) {:.3e}; K by AMD(K): stored {:.3e} exact {:.3e}; by after-DOFs: stored {:.3e} exact {:.3e}",
            p.dofs(),
            p.rows(),
            a_pattern.stored_values() as f64,
            nnz(&o_k) as f64,
            exact(&o_k) as f64,
            nnz(&o_after) as f64,
            exact(&o_after) as f64,
        );
    }
}

/// One ordering, 20 times, chosen by `VARIANT` (`amd_a`: A as stored, both triangles;
/// `lower_a`: A's lower triangle, as K stores it; `amd_k`: K by plain AMD; `nodes_k`: K by
/// pdas's own [`signorini_qp::linalg::kkt_order`]; anything else: none, the baseline), on the Tresca strip, for `perf stat -e task-clock` (CPU time moves less with the
/// machine's load than wall time; this machine exposes no instruction counters):
///
/// ```text
/// VARIANT=amd_k perf stat -e task-clock target/release/deps/pdas_measure-* \
///   --ignored --exact amd_variant_for_perf_stat
/// ```
#[test]
#[ignore = "measurement, run by hand"]
fn amd_variant_for_perf_stat() {
    use signorini_core::scene::Friction;
    let mut scene = common::strip_scene(20.0, false, (0.0, 20.0));
    scene.contacts[0].friction = Some(Friction::Tresca(1e-4));
    let p = signorini_core::solve::ScaledQp::new(common::qp_of(&scene)).problem;
    // K's lower pattern as a CSC matrix (the values do not matter to an ordering).
    let k = &signorini_qp::linalg::kkt::kkt_pattern(&p.stiffness, &p.constraints).unwrap();
    let n = p.dofs();
    let mut lower = sprs::TriMat::new((n, n));
    for (v, (i, j)) in p.stiffness.iter() {
        if i >= j {
            lower.add_triplet(i, j, *v);
        }
    }
    let lower_a: signorini_qp::CscMatrix = lower.to_csc();
    let variant = std::env::var("VARIANT").unwrap_or_default();
    for _ in 0..20 {
        match variant.as_str() {
            "amd_a" => drop(fill_reducing_order(&p.stiffness).unwrap()),
            "lower_a" => drop(fill_reducing_order(&lower_a).unwrap()),
            "amd_k" => drop(fill_reducing_order(k).unwrap()),
            "nodes_k" => {
                let (xadj, adjncy) = signorini_qp::linalg::ordering::adjacency(k).unwrap();
                drop(signorini_qp::linalg::kkt_order(&xadj, &adjncy).unwrap())
            }
            _ => {}
        }
    }
}
