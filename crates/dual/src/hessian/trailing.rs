//! H read off the factor with the contact DOFs ordered last: H = Yᵀ Y, Y = L_cc⁻¹ B_cᵀ.

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Accum, Mat, MatRef, Par};
use signorini_qp::CscMatrix;

use super::dense::DenseSym;

/// H = Yᵀ Y with Y = L_cc⁻¹ B_cᵀ; `touched[k]` is the full DOF of row/column k of L_cc.
pub fn trailing_hessian(
    factor: MatRef<'_, f64>,
    touched: &[usize],
    constraints: &CscMatrix,
) -> DenseSym {
    let m = constraints.rows();
    let mut y = Mat::<f64>::zeros(touched.len(), m);
    for (k, &j) in touched.iter().enumerate() {
        if let Some(col) = constraints.outer_view(j) {
            for (i, &v) in col.iter() {
                y[(k, i)] = v;
            }
        }
    }
    solve_lower_triangular_in_place(factor, y.as_mut(), Par::Seq);
    let mut h = Mat::<f64>::zeros(m, m);
    matmul(
        h.as_mut(),
        Accum::Replace,
        y.transpose(),
        y.as_ref(),
        1.0,
        Par::Seq,
    );
    let mut values = vec![0.0; m * m];
    for j in 0..m {
        for i in 0..m {
            values[j * m + i] = 0.5 * (h[(i, j)] + h[(j, i)]);
        }
    }
    DenseSym { values, size: m }
}
