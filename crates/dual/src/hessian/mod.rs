//! Condensation of A onto the contact rows: the dense dual Hessian H = B A⁺ Bᵀ (m × m).
//!
//! Three ways, one file each: [`trailing`] reads H off the factor with the contact DOFs last
//! (the default; see [`crate::factor`]); [`multi_rhs`] solves A Y = Bᵀ for blocks of
//! `block_size` right-hand sides with the cached factor and keeps only B Y; [`schur`] forms the
//! Schur complement of A on the touched DOFs.  [`dense`] holds the result type.

mod dense;
mod multi_rhs;
mod schur;
mod trailing;

pub use dense::{power_iteration, DenseSym};
pub use multi_rhs::multi_rhs;
#[cfg(test)]
pub use multi_rhs::touched_columns;
pub use schur::interior_schur;
pub use trailing::trailing_hessian;

use crate::dual::DualData;
use crate::error::DualError;
use crate::settings::{Condensation, DualSettings};

/// H = B A⁺ Bᵀ by the strategy of `settings`.
pub fn dual_hessian(data: &DualData<'_>, settings: &DualSettings) -> Result<DenseSym, DualError> {
    if data.inverse.contact_last() {
        return Ok(trailing_hessian(
            data.inverse.factor().trailing(),
            data.inverse.trailing(),
            &data.problem.constraints,
        ));
    }
    match settings.condensation {
        // Too many contact DOFs to order last: fall back to multi-RHS solves.
        Condensation::TrailingBlock | Condensation::MultiRhs => Ok(multi_rhs(
            &data.inverse,
            &data.problem.constraints,
            settings.block_size,
        )),
        Condensation::InteriorSchur => interior_schur(data, settings.block_size),
    }
}
