//! Small sparse and dense kernels shared by the QP code and the backends.

use sprs::CsMat;

/// Sparse matrix type of the QP: compressed sparse columns, `f64` values.
pub type CscMatrix = CsMat<f64>;

/// Column pointers, row indices and values of a CSC matrix, keeping only the entries with
/// `keep(row, col)` (e.g. `|i, j| i <= j` for the upper triangle solvers want); rows stay sorted
/// within each column.
pub fn csc_parts(
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

/// y = M x for a CSC matrix.
pub fn mat_vec(m: &CscMatrix, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; m.rows()];
    for (j, col) in m.outer_iterator().enumerate() {
        let xj = x[j];
        if xj != 0.0 {
            for (i, v) in col.iter() {
                y[i] += v * xj;
            }
        }
    }
    y
}

/// y = Mᵀ x for a CSC matrix.
pub fn mat_t_vec(m: &CscMatrix, x: &[f64]) -> Vec<f64> {
    m.outer_iterator()
        .map(|col| col.iter().map(|(i, v)| v * x[i]).sum())
        .collect()
}

/// Dot product.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Largest absolute entry (0 for an empty slice).
pub fn norm_inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// |Mⱼⱼ| of every column j of a square CSC matrix (0 where none is stored), read column by
/// column: rows are sorted within a column, so each is one binary search.
pub(crate) fn abs_diagonal(m: &CscMatrix) -> Vec<f64> {
    m.outer_iterator()
        .enumerate()
        .map(|(j, col)| {
            let (rows, values) = (col.indices(), col.data());
            rows.binary_search(&j).map_or(0.0, |at| values[at].abs())
        })
        .collect()
}
