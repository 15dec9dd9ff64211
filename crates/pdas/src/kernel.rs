//! Floating bodies: checks of the known kernel R of A and the two ways a rigid motion makes the
//! objective unbounded below (dual infeasibility).

use signorini_qp::{dot, mat_vec, norm_inf, QpProblem};

use crate::dense::DenseLu;
use crate::error::PdasError;

/// Relative size below which a direction counts as dependent on the others.
const DEPENDENCE: f64 = 1e-10;

/// Relative residual ‖A r‖∞ / (max|A| ‖r‖∞) above which a vector is not in the kernel.
const KERNEL_RESIDUAL: f64 = 1e-8;

/// Checks that every kernel vector lies in the null space of A.
pub fn check_kernel(problem: &QpProblem) -> Result<(), PdasError> {
    let a_max = norm_inf(problem.stiffness.data());
    for (index, r) in problem.kernel.iter().enumerate() {
        let size = norm_inf(r);
        let residual = if size == 0.0 {
            // The zero vector spans nothing.
            f64::INFINITY
        } else if a_max == 0.0 {
            // A = 0: every vector is in its kernel.
            0.0
        } else {
            norm_inf(&mat_vec(&problem.stiffness, r)) / (a_max * size)
        };
        if residual.is_nan() || residual > KERNEL_RESIDUAL {
            return Err(PdasError::NotAKernelVector { index, residual });
        }
    }
    Ok(())
}

/// A rigid motion no contact row sees but the load drives: a combination v with B R v = 0 and
/// fᵀ R v ≠ 0 (Gram–Schmidt on the vectors B rⱼ, carrying fᵀ rⱼ along).  Returns the index of
/// the first kernel vector found dependent on the previous ones with a load left on it.
pub fn unrestrained_mode(problem: &QpProblem) -> Option<usize> {
    let load_norm = norm_inf(&problem.load);
    let mut q_rows: Vec<(Vec<f64>, f64)> = Vec::new();
    for (j, r) in problem.kernel.iter().enumerate() {
        let row = mat_vec(&problem.constraints, r);
        let e = dot(r, &problem.load);
        let mut v = row.clone();
        let mut ev = e;
        for (q, qe) in &q_rows {
            let p = dot(q, &v);
            v.iter_mut().zip(q).for_each(|(vi, qi)| *vi -= p * qi);
            ev -= p * qe;
        }
        let row_norm = dot(&row, &row).sqrt();
        let v_norm = dot(&v, &v).sqrt();
        let r_norm = dot(r, r).sqrt();
        if row_norm == 0.0 || v_norm <= DEPENDENCE * row_norm {
            if ev.abs() > 1e-9 * r_norm * load_norm {
                return Some(j);
            }
        } else {
            q_rows.push((v.iter().map(|x| x / v_norm).collect(), ev / v_norm));
        }
    }
    None
}

/// The rigid part of `x`: r = R α with α the least-squares coefficients (RᵀR α = Rᵀ x).
/// `None` without a kernel or when RᵀR is singular.
pub fn rigid_part(kernel: &[Vec<f64>], x: &[f64]) -> Option<Vec<f64>> {
    let k = kernel.len();
    if k == 0 {
        return None;
    }
    let mut gram = vec![0.0; k * k];
    let mut rhs: Vec<f64> = kernel.iter().map(|r| dot(r, x)).collect();
    for i in 0..k {
        for j in 0..k {
            gram[i * k + j] = dot(&kernel[i], &kernel[j]);
        }
    }
    DenseLu::new(gram, k)?.solve_in_place(&mut rhs);
    let alpha = rhs;
    let mut r = vec![0.0; x.len()];
    for (v, a) in kernel.iter().zip(&alpha) {
        r.iter_mut().zip(v).for_each(|(ri, vi)| *ri += a * vi);
    }
    Some(r)
}

/// A certificate of dual infeasibility in the rigid part r of an iterate: fᵀ r > 0 (the load
/// lowers the energy along r, which costs no strain energy) and B r ≤ 0 up to round-off (no
/// contact row closes along r).  Returns fᵀ r / ‖r‖∞ when both hold.
pub fn pushed_away(problem: &QpProblem, r: &[f64]) -> Option<f64> {
    let size = norm_inf(r);
    if size == 0.0 || !size.is_finite() {
        return None;
    }
    let unit: Vec<f64> = r.iter().map(|v| v / size).collect();
    let work = dot(&problem.load, &unit);
    let b_max = norm_inf(problem.constraints.data());
    let closing = mat_vec(&problem.constraints, &unit)
        .into_iter()
        .fold(0.0_f64, f64::max);
    let load_norm = norm_inf(&problem.load);
    (work > 1e-9 * load_norm && closing <= 1e-9 * b_max).then_some(work)
}

#[cfg(test)]
mod tests {
    use super::*;
    use signorini_qp::examples::csc;

    #[test]
    fn rigid_part_recovers_a_kernel_combination() {
        let kernel = vec![vec![1.0, 1.0, 1.0], vec![0.0, 1.0, 2.0]];
        let x = vec![2.0 + 0.1, 2.0 + 3.0 - 0.2, 2.0 + 6.0 + 0.1];
        let r = rigid_part(&kernel, &x).unwrap();
        // x = 2·(1,1,1) + 3·(0,1,2) + (0.1, −0.2, 0.1), the last part orthogonal to both.
        for (ri, e) in r.iter().zip([2.0, 5.0, 8.0]) {
            assert!((ri - e).abs() < 1e-12, "{r:?}");
        }
    }

    #[test]
    fn a_mode_without_rows_but_with_load_is_unrestrained() {
        // Two free unit masses joined by a spring: kernel (1, 1); a row only on x0 − x1.
        let a = csc(2, 2, &[&[1.0, -1.0], &[-1.0, 1.0]]);
        let b = csc(1, 2, &[&[1.0, -1.0]]);
        let p = QpProblem::try_new(a, vec![1.0, 0.0], b, vec![1.0])
            .unwrap()
            .with_kernel(vec![vec![1.0, 1.0]])
            .unwrap();
        assert!(check_kernel(&p).is_ok());
        assert_eq!(unrestrained_mode(&p), Some(0));
        // The rigid motion (1, 1) moves along the load and does not close the row.
        assert!(pushed_away(&p, &[1.0, 1.0]).is_some());
        assert!(pushed_away(&p, &[-1.0, -1.0]).is_none());
    }
}
