//! H = B (A⁺ Bᵀ) by multi-right-hand-side solves with the cached factor.

use std::ops::Range;

use signorini_qp::CscMatrix;

use super::dense::DenseSym;
use crate::error::DualError;
use crate::factor::StiffnessInverse;

/// Columns of B with at least one entry that are not fixed: (full index, reduced index).
pub fn touched_columns(inverse: &StiffnessInverse, constraints: &CscMatrix) -> Vec<(usize, usize)> {
    constraints
        .outer_iterator()
        .enumerate()
        .filter(|(_, col)| col.nnz() > 0)
        .filter_map(|(j, _)| inverse.reduced_index(j).map(|r| (j, r)))
        .collect()
}

/// Runs `solve` on the blocks of at most `block` of `total` right-hand sides, in order,
/// checking `out_of_time` before each: once it says so, [`DualError::OutOfTime`]
/// "while `what` (k of `total` columns)".
pub fn in_blocks(
    total: usize,
    block: usize,
    what: &str,
    out_of_time: &dyn Fn() -> bool,
    mut solve: impl FnMut(Range<usize>),
) -> Result<(), DualError> {
    for start in (0..total).step_by(block) {
        if out_of_time() {
            return Err(DualError::OutOfTime(format!(
                "while {what} ({start} of {total} columns)"
            )));
        }
        solve(start..start + block.min(total - start));
    }
    Ok(())
}

/// H = B (A⁺ Bᵀ), blocks of `block` right-hand sides at a time; stops with
/// [`DualError::OutOfTime`] between blocks once `out_of_time` says so.
pub fn multi_rhs(
    inverse: &StiffnessInverse,
    constraints: &CscMatrix,
    block: usize,
    out_of_time: &dyn Fn() -> bool,
) -> Result<DenseSym, DualError> {
    let m = constraints.rows();
    let nr = inverse.reduced_dim();
    let rows = constraints.to_csr();
    let touched = touched_columns(inverse, constraints);
    let mut h = DenseSym {
        values: vec![0.0; m * m],
        size: m,
    };
    let mut work = vec![0.0; nr * block.min(m.max(1))];
    let what = "forming the dense dual Hessian by multi-right-hand-side solves";
    in_blocks(m, block, what, out_of_time, |columns| {
        let (start, count) = (columns.start, columns.len());
        let work = &mut work[..nr * count];
        work.fill(0.0);
        for k in 0..count {
            if let Some(row) = rows.outer_view(start + k) {
                for (j, v) in row.iter() {
                    if let Some(r) = inverse.reduced_index(j) {
                        work[k * nr + r] += v;
                    }
                }
            }
        }
        inverse.solve_reduced_many(work);
        for k in 0..count {
            let y = &work[k * nr..(k + 1) * nr];
            let col = &mut h.values[(start + k) * m..(start + k + 1) * m];
            for &(j, r) in &touched {
                let yr = y[r];
                if yr != 0.0 {
                    if let Some(bcol) = constraints.outer_view(j) {
                        for (i, v) in bcol.iter() {
                            col[i] += v * yr;
                        }
                    }
                }
            }
        }
    })?;
    h.symmetrise();
    Ok(h)
}
