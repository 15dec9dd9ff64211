//! Contact rows as entries of B: every pair's normal rows, then the tangential rows of the
//! frictional pairs (`friction.rs`).

use sprs::TriMat;

use super::friction::TangentialRow;
use crate::contact::{ContactRow, PairRows};
use crate::fem::Dofs;
use crate::geometry::tangent;
use crate::geometry::Point;
use crate::qp::CscMatrix;

/// The contact matrix B on all DOFs and the initial gaps g: the normal rows in pair order, then
/// one row per entry of `tangential`, whose gap k gₙ is where its node sticks (`friction.rs`).
pub(super) fn contact_matrix(
    contacts: &[PairRows],
    tangential: &[TangentialRow],
    dofs: &Dofs,
) -> (CscMatrix, Vec<f64>) {
    let normal: Vec<(&PairRows, &ContactRow)> = contacts
        .iter()
        .flat_map(|pair| pair.rows.iter().map(move |r| (pair, r)))
        .collect();
    let m = normal.len() + tangential.len();
    let mut b = TriMat::with_capacity((m, dofs.len()), 6 * m);
    let mut gap = Vec::with_capacity(m);
    for (row, (pair, r)) in normal.iter().enumerate() {
        for (d, v) in row_entries(dofs, pair, r) {
            b.add_triplet(row, d, v);
        }
        gap.push(r.gap);
    }
    for (k, t) in tangential.iter().enumerate() {
        let (pair, r) = normal[t.normal_row];
        for (d, v) in entries_along(dofs, pair, r, tangent(r.normal)) {
            b.add_triplet(normal.len() + k, d, v);
        }
        gap.push(r.pairing_slope * r.gap);
    }
    (b.to_csc(), gap)
}

/// The entries (DOF, coefficient) of a contact row of B, in the order B stores them: for each
/// component c, the slave node's −n_c, then w_k n_c on each master node k with a non-zero weight.
pub(super) fn row_entries(dofs: &Dofs, pair: &PairRows, r: &ContactRow) -> Vec<(usize, f64)> {
    entries_along(dofs, pair, r, r.normal)
}

/// The entries of the row of node `r` along `direction` (its normal or its tangent).
fn entries_along(
    dofs: &Dofs,
    pair: &PairRows,
    r: &ContactRow,
    direction: Point,
) -> Vec<(usize, f64)> {
    let mut entries = Vec::with_capacity(2 + 2 * r.masters.len());
    for (c, &nc) in direction.iter().enumerate() {
        entries.push((dofs.dof(pair.slave, r.slave_node, c), -nc));
        for &(k, w) in &r.masters {
            if w != 0.0 {
                entries.push((dofs.dof(pair.master, k, c), w * nc));
            }
        }
    }
    entries
}
