//! Mortar contact rows (segment-to-segment, dual Lagrange multipliers): see `contact/mod.rs`.
//!
//! Placeholder of the skeleton: builds node-to-segment rows until the mortar integration lands.

use super::{pair_rows as node_to_segment, Built, Search};
use crate::mesh::Mesh;

/// The mortar rows of one pair: one row per slave node that the master covers.
pub(super) fn pair_rows(
    slave: &Mesh,
    master: &Mesh,
    cand_s: &[bool],
    cand_m: &[bool],
    inside_s: &[Option<f64>],
    tol: f64,
    limit: f64,
) -> Built {
    node_to_segment(
        slave,
        master,
        cand_s,
        cand_m,
        inside_s,
        tol,
        limit,
        Search::Indexed,
    )
}
