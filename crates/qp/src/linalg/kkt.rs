//! The sparsity pattern of the quasidefinite KKT matrix an interior-point or ADMM solver factors,
//!
//! ```text
//! K = [ A + σI   Bᵀ ]        (n + m) × (n + m)
//!     [ B       −D  ]        D diagonal (clarabel: W² + εI; OSQP: ρ⁻¹ I)
//! ```
//!
//! so that the size of its LDLᵀ factor is known from the symbolic analysis
//! ([`super::CholeskyPattern`], AMD as every factor of the project) before the solver allocates
//! it.  The values are irrelevant (all ones): only the pattern is analysed.

use super::LinalgError;
use crate::CscMatrix;

/// Stored entries of the lower triangle of K (an upper bound when A stores entries twice):
/// what [`kkt_pattern`] allocates, so that a caller can check it fits before building it.
pub fn kkt_pattern_entries(stiffness: &CscMatrix, constraints: &CscMatrix) -> usize {
    let n = stiffness.cols();
    // A's lower triangle and its diagonal, all of B, D's diagonal.
    (stiffness.nnz() + n) / 2 + n + constraints.nnz() + constraints.rows()
}

/// The lower triangle of K's pattern in CSC (columns sorted, no duplicates), all values 1.
/// Either triangle of A (or both) may be stored; the diagonal of A + σI and of D is always in
/// the pattern, as the solvers' regularisation puts it there.
///
/// # Errors
/// [`LinalgError::Shape`] when A is not square or B's columns are not A's.
pub fn kkt_pattern(
    stiffness: &CscMatrix,
    constraints: &CscMatrix,
) -> Result<CscMatrix, LinalgError> {
    let n = stiffness.rows();
    let m = constraints.rows();
    if stiffness.cols() != n || constraints.cols() != n {
        return Err(LinalgError::Shape {
            rows: constraints.rows(),
            cols: constraints.cols(),
        });
    }
    let a = stiffness.to_csc();
    let b = constraints.to_csc();
    // Column j of the lower triangle of A ∪ Aᵀ gets (max, min) of every stored (i, j).
    let mut columns: Vec<Vec<usize>> = (0..n).map(|j| vec![j]).collect();
    for (j, col) in a.outer_iterator().enumerate() {
        for (i, _) in col.iter() {
            columns[i.min(j)].push(i.max(j));
        }
    }
    for (j, col) in b.outer_iterator().enumerate() {
        columns[j].extend(col.iter().map(|(r, _)| n + r));
    }
    let mut indptr = Vec::with_capacity(n + m + 1);
    let mut indices = Vec::with_capacity(kkt_pattern_entries(&a, &b));
    indptr.push(0);
    for mut rows in columns {
        rows.sort_unstable();
        rows.dedup();
        indices.extend(rows);
        indptr.push(indices.len());
    }
    for r in 0..m {
        indices.push(n + r);
        indptr.push(indices.len());
    }
    let values = vec![1.0; indices.len()];
    CscMatrix::try_new_csc((n + m, n + m), indptr, indices, values)
        .map_err(|e| LinalgError::Faer(format!("building the KKT pattern: {}", e.3)))
}

/// The adjacency graph of K's pattern (without the diagonal, each edge both ways) in CSR,
/// `(xadj, adjncy)`, read straight off A and B: vertex j < n neighbours the other rows of A's
/// column j and the multipliers n + r of B's column j; vertex n + r the DOFs of B's row r.
/// A must store both triangles (as [`crate::QpProblem`] does); B's entries may be zeros.
///
/// # Errors
/// [`LinalgError::Shape`] when A is not square or B's columns are not A's.
pub fn kkt_graph(
    stiffness: &CscMatrix,
    constraints: &CscMatrix,
) -> Result<(Vec<usize>, Vec<usize>), LinalgError> {
    let n = stiffness.rows();
    let m = constraints.rows();
    if stiffness.cols() != n || constraints.cols() != n || !stiffness.is_csc() {
        return Err(LinalgError::Shape {
            rows: constraints.rows(),
            cols: constraints.cols(),
        });
    }
    let b = constraints.to_csc();
    let mut row_degree = vec![0usize; m];
    for (_, (r, _)) in b.iter() {
        row_degree[r] += 1;
    }
    let mut xadj = Vec::with_capacity(n + m + 1);
    xadj.push(0);
    for (j, col) in stiffness.outer_iterator().enumerate() {
        let off_diagonal = col.iter().filter(|&(i, _)| i != j).count();
        let in_b = b.outer_view(j).map_or(0, |c| c.nnz());
        xadj.push(xadj[j] + off_diagonal + in_b);
    }
    for r in 0..m {
        xadj.push(xadj[n + r] + row_degree[r]);
    }
    let mut adjncy = vec![0usize; xadj[n + m]];
    let mut next_of_row: Vec<usize> = xadj[n..n + m].to_vec();
    for (j, col) in stiffness.outer_iterator().enumerate() {
        let mut at = xadj[j];
        for (i, _) in col.iter().filter(|&(i, _)| i != j) {
            adjncy[at] = i;
            at += 1;
        }
        if let Some(b_col) = b.outer_view(j) {
            for (r, _) in b_col.iter() {
                adjncy[at] = n + r;
                at += 1;
                adjncy[next_of_row[r]] = j;
                next_of_row[r] += 1;
            }
        }
    }
    Ok((xadj, adjncy))
}

#[cfg(test)]
mod tests {
    use super::*;
    use sprs::TriMat;

    /// Read straight off A and B, the graph is the adjacency of K's pattern (as lists).
    #[test]
    fn the_graph_is_that_of_the_pattern() {
        use crate::examples::two_dof_grid;
        let a = two_dof_grid(4);
        let n = a.rows();
        let mut b = TriMat::new((3, n));
        for (r, j, v) in [
            (0, 1, 1.0),
            (0, 6, -0.5),
            (1, 6, 2.0),
            (2, 31, 1.0),
            (2, 0, 0.0),
        ] {
            b.add_triplet(r, j, v);
        }
        let b = b.to_csc();
        let lists = |(x, a): (Vec<usize>, Vec<usize>)| -> Vec<Vec<usize>> {
            (0..x.len() - 1)
                .map(|v| {
                    let mut l = a[x[v]..x[v + 1]].to_vec();
                    l.sort_unstable();
                    l
                })
                .collect()
        };
        let direct = lists(kkt_graph(&a, &b).unwrap());
        let pattern = kkt_pattern(&a, &b).unwrap();
        let via_pattern = lists(super::super::ordering::adjacency(&pattern).unwrap());
        assert_eq!(direct, via_pattern);
        // Multiplier 0 touches DOFs 1 and 6; DOF 6 sees multipliers 0 and 1 (n, n + 1).
        assert_eq!(direct[n], vec![1, 6]);
        assert!(direct[6].ends_with(&[n, n + 1]));
    }

    #[test]
    fn the_pattern_is_the_lower_triangle_of_both_blocks_with_full_diagonal() {
        // A = [2 1; 1 2] stored full, B = [0 1] (one row on x₁).
        let mut a = TriMat::new((2, 2));
        for (i, j, v) in [(0, 0, 2.0), (1, 1, 2.0), (0, 1, 1.0), (1, 0, 1.0)] {
            a.add_triplet(i, j, v);
        }
        let mut b = TriMat::new((1, 2));
        b.add_triplet(0, 1, 1.0);
        let k = kkt_pattern(&a.to_csc(), &b.to_csc()).unwrap();
        let entries: Vec<(usize, usize)> = k.iter().map(|(_, (i, j))| (i, j)).collect();
        assert_eq!(entries, vec![(0, 0), (1, 0), (1, 1), (2, 1), (2, 2)]);
        assert!(k.nnz() <= kkt_pattern_entries(&a.to_csc(), &b.to_csc()));
    }

    #[test]
    fn an_upper_triangle_gives_the_same_pattern() {
        let mut full = TriMat::new((3, 3));
        let mut upper = TriMat::new((3, 3));
        for (i, j) in [(0, 0), (1, 1), (2, 2), (0, 2)] {
            full.add_triplet(i, j, 1.0);
            upper.add_triplet(i, j, 1.0);
            if i != j {
                full.add_triplet(j, i, 1.0);
            }
        }
        let b = TriMat::<f64>::new((0, 3)).to_csc();
        let p = |a: &TriMat<f64>| {
            let k = kkt_pattern(&a.to_csc(), &b).unwrap();
            k.iter().map(|(_, (i, j))| (i, j)).collect::<Vec<_>>()
        };
        assert_eq!(p(&full), p(&upper));
        // A diagonal entry A does not store is in the pattern (A + σI).
        let mut gap = TriMat::new((3, 3));
        gap.add_triplet(0, 2, 1.0);
        assert_eq!(p(&gap), p(&full));
    }
}
