//! # signorini-qp
//!
//! The QP contract of signorini: the quadratic program every backend solves, the one residual
//! check used for all of them, the backend trait, and what the backends share — the sparse
//! factor path ([`linalg`]), the memory guards ([`memory`]) and QPs with known optima
//! ([`examples`]).  Backend crates depend on this crate alone, never on the model (scene, mesh,
//! FEM, contact) that builds the problems.
//!
//! ```text
//! minimise   ½ xᵀ A x − fᵀ x
//! subject to B x ≤ g
//! ```
//!
//! `A` (`stiffness`, n×n) is the symmetric positive (semi-)definite stiffness on the free degrees
//! of freedom, `f` (`load`) the load vector after Dirichlet lifting, `B` (`constraints`, m×n) the
//! node-to-segment contact rows and `g` (`gap`) the initial normal gaps.  The KKT conditions are
//!
//! ```text
//! A x − f + Bᵀ λ = 0,   B x ≤ g,   λ ≥ 0,   λᵢ (g − B x)ᵢ = 0,
//! ```
//!
//! with λ the contact forces.  [`kkt_residuals`] measures how far a pair (x, λ) is from them, the
//! same way for every backend, and [`checked_status`] turns a backend's own verdict into the
//! status the program reports: `solved` only when these residuals meet the requested tolerance.
//! This is the frictionless problem; friction (Tresca, and Coulomb through [`CoulombRows`]) adds
//! box rows with bounded multipliers |λᵢ| ≤ sᵢ after the contact rows ([`ConstraintBlock`]).

pub mod conformance;
pub mod examples;
pub mod linalg;
pub mod memory;

mod auxiliary;
mod backend;
mod blocks;
mod bodies;
mod certificate;
mod coulomb;
mod dual_form;
mod ops;
mod problem;
mod residuals;
mod scales;
mod scaling;
mod solution;
mod status;

#[cfg(test)]
mod tests;

pub use auxiliary::AuxiliaryForm;
pub use backend::{QpBackend, QpSolution, SolveOptions, WarmStart};
pub use blocks::{project, row_sets, BlockKind, ConstraintBlock, RowSet};
pub use bodies::{first_touch, Components, ContactBody};
pub use certificate::{FarkasRay, FARKAS_MARGIN};
pub use coulomb::{CoulombLink, CoulombMethod, CoulombRows};
pub use dual_form::{
    condensable, condense, primal_of, touched_dofs, CondenseStop, Condensed, CondensedDual,
    BYTES_PER_DUAL_ENTRY,
};
pub use ops::{csc_parts, dot, mat_t_vec, mat_vec, norm_inf};
pub use problem::{CscMatrix, QpError, QpProblem};
pub use residuals::{
    kkt_residuals, kkt_residuals_in, kkt_residuals_with, KktResiduals, ResidualScales,
    BODY_FORCE_FLOOR, BODY_MOTION_FLOOR,
};
pub use scaling::QpScaling;
pub use status::{checked_status, QpStatus};
