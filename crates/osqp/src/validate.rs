//! Checks a [`QpProblem`] before any of it reaches OSQP (whose constructors assert).

use signorini_core::qp::{CscMatrix, QpError, QpProblem};

/// Checks dimensions, CSC storage and finiteness; the fields of a `QpProblem` are public, so
/// it may not have gone through `QpProblem::try_new`.
pub(crate) fn check_problem(problem: &QpProblem) -> Result<(), QpError> {
    let n = problem.stiffness.rows();
    if problem.stiffness.cols() != n {
        return Err(QpError::Dimensions(format!(
            "A is {}×{}, not square",
            n,
            problem.stiffness.cols()
        )));
    }
    if problem.load.len() != n {
        return Err(QpError::Dimensions(format!(
            "f has length {} but A is {n}×{n}",
            problem.load.len()
        )));
    }
    if problem.constraints.cols() != n {
        return Err(QpError::Dimensions(format!(
            "B has {} columns but A is {n}×{n}",
            problem.constraints.cols()
        )));
    }
    if problem.gap.len() != problem.constraints.rows() {
        return Err(QpError::Dimensions(format!(
            "g has length {} but B has {} rows",
            problem.gap.len(),
            problem.constraints.rows()
        )));
    }
    if !problem.stiffness.is_csc() {
        return Err(QpError::NotCsc("A"));
    }
    if !problem.constraints.is_csc() {
        return Err(QpError::NotCsc("B"));
    }
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    if !finite(problem.stiffness.data()) {
        return Err(QpError::NotFinite("A"));
    }
    if !finite(&problem.load) {
        return Err(QpError::NotFinite("f"));
    }
    if !finite(problem.constraints.data()) {
        return Err(QpError::NotFinite("B"));
    }
    if !finite(&problem.gap) {
        return Err(QpError::NotFinite("g"));
    }
    Ok(())
}

/// Column pointers, row indices and values of `matrix` (CSC), keeping only entries with
/// `keep(row, col)`; rows come out sorted within each column, as sprs stores them.
pub(crate) fn csc_parts(
    matrix: &CscMatrix,
    keep: impl Fn(usize, usize) -> bool,
) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let mut colptr = Vec::with_capacity(matrix.cols() + 1);
    let mut rows = Vec::with_capacity(matrix.nnz());
    let mut values = Vec::with_capacity(matrix.nnz());
    colptr.push(0);
    for (col, column) in matrix.outer_iterator().enumerate() {
        for (row, &value) in column.iter() {
            if keep(row, col) {
                rows.push(row);
                values.push(value);
            }
        }
        colptr.push(rows.len());
    }
    (colptr, rows, values)
}
