//! # signorini-core
//!
//! Contact of linear-elastic bodies in 2D by finite elements: frictionless, or with Tresca or
//! Coulomb friction.  A scene (TOML) names bodies, supports, loads and contact pairs (with their
//! friction law); the pipeline is
//!
//! ```text
//! scene ──mesh──▶ meshes ──assemble──▶ model {A, f, B, g} ──▶ QpProblem ──backend──▶ (x, λ)
//!       ──▶ residuals (same for every backend) ──▶ report
//! ```
//!
//! and the discrete contact problem is the quadratic program
//!
//! ```text
//! minimise ½ uᵀ A u − fᵀ u   subject to   B u ≤ g,
//! ```
//!
//! with A the stiffness on the free degrees of freedom, f the loads, B the node-to-segment
//! contact rows and g the initial gaps.  Friction adds the tangential rows as a box block
//! (|λᵢ| ≤ sᵢ, the term sᵢ |(B u − g)ᵢ| in the objective: see [`qp::ConstraintBlock`]): Tresca's
//! bounds sᵢ are given, Coulomb's are μ max(0, λₙ) of the normal multiplier, solved by a
//! backend's own method or a fixed point over Tresca problems ([`solve`]).  Backends implement
//! [`qp::QpBackend`].

pub use signorini_qp as qp;
pub use signorini_qp::{examples, linalg, memory};

pub mod accuracy;
pub mod contact;
pub mod effects;
pub mod fem;
pub mod geometry;
#[cfg(test)]
mod linalg_measure;
pub mod mesh;
pub mod model;
pub mod preflight;
pub mod report;
pub mod scene;
pub mod solve;
