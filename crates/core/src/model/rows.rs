//! Contact rows as entries of B.

use sprs::TriMat;

use crate::contact::{ContactRow, PairRows};
use crate::fem::Dofs;
use crate::qp::CscMatrix;

/// The contact matrix B on all DOFs (rows in pair order) and the initial gaps g.
pub(super) fn contact_matrix(contacts: &[PairRows], dofs: &Dofs) -> (CscMatrix, Vec<f64>) {
    let m: usize = contacts.iter().map(|p| p.rows.len()).sum();
    let mut b = TriMat::with_capacity((m, dofs.len()), 6 * m);
    let mut gap = Vec::with_capacity(m);
    for (row, (pair, r)) in contacts
        .iter()
        .flat_map(|pair| pair.rows.iter().map(move |r| (pair, r)))
        .enumerate()
    {
        for (d, v) in row_entries(dofs, pair, r) {
            b.add_triplet(row, d, v);
        }
        gap.push(r.gap);
    }
    (b.to_csc(), gap)
}

/// The entries (DOF, coefficient) of a contact row of B, in the order B stores them: for each
/// component c, the slave node's −n_c, then w_k n_c on each master node k with a non-zero weight.
pub(super) fn row_entries(dofs: &Dofs, pair: &PairRows, r: &ContactRow) -> Vec<(usize, f64)> {
    let mut entries = Vec::with_capacity(2 + 2 * r.masters.len());
    for (c, &nc) in r.normal.iter().enumerate() {
        entries.push((dofs.dof(pair.slave, r.slave_node, c), -nc));
        for &(k, w) in &r.masters {
            if w != 0.0 {
                entries.push((dofs.dof(pair.master, k, c), w * nc));
            }
        }
    }
    entries
}
