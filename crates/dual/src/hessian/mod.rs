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

/// Bytes the formation of H by the strategy of `settings` allocates at its peak, plus
/// `extra_squares` further m × m arrays the method keeps (e.g. the dense Newton matrix and its
/// factor).
pub fn dense_bytes(data: &DualData<'_>, settings: &DualSettings, extra_squares: f64) -> f64 {
    let m = data.rows() as f64;
    let c = data.inverse.trailing().len() as f64;
    let words = if data.inverse.contact_last() {
        c * m + 2.0 * m * m
    } else {
        match settings.condensation {
            Condensation::TrailingBlock | Condensation::MultiRhs => {
                m * m + data.inverse.reduced_dim() as f64 * settings.block_size as f64
            }
            Condensation::InteriorSchur => {
                let c = touched_count(data) as f64;
                3.0 * c * c + 2.0 * c * m + 2.0 * m * m
            }
        }
    };
    8.0 * (words + extra_squares * m * m)
}

fn touched_count(data: &DualData<'_>) -> usize {
    multi_rhs::touched_columns(&data.inverse, &data.problem.constraints).len()
}

/// H = B A⁺ Bᵀ by the strategy of `settings`, after checking that it fits in memory
/// (`QpError::TooLarge` through [`DualError::Refused`]); the multi-right-hand-side loops stop
/// with [`DualError::OutOfTime`] once `out_of_time` says so (checked between blocks, so the
/// overshoot is one block of solves).
pub fn dual_hessian(
    data: &DualData<'_>,
    settings: &DualSettings,
    extra_squares: f64,
    out_of_time: &dyn Fn() -> bool,
) -> Result<DenseSym, DualError> {
    let m = data.rows();
    let bytes = dense_bytes(data, settings, extra_squares);
    signorini_qp::memory::check_fits(
        settings.method.backend_name(),
        || format!("the dense dual Hessian H = B A⁻¹ Bᵀ ({m} × {m}) and its work arrays"),
        bytes,
    )?;
    if data.inverse.contact_last() {
        return Ok(trailing_hessian(
            data.inverse.factor().trailing(),
            data.inverse.trailing(),
            &data.problem.constraints,
        ));
    }
    match settings.condensation {
        // Too many contact DOFs to order last: fall back to multi-RHS solves.
        Condensation::TrailingBlock | Condensation::MultiRhs => multi_rhs(
            &data.inverse,
            &data.problem.constraints,
            settings.block_size,
            out_of_time,
        ),
        Condensation::InteriorSchur => interior_schur(data, settings.block_size, out_of_time),
    }
}
