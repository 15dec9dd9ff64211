//! # signorini-core
//!
//! Frictionless contact of linear-elastic bodies in 2D by finite elements.  A scene (TOML) names
//! bodies, supports, loads and contact pairs; the pipeline is
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
//! contact rows and g the initial gaps.  Backends implement [`qp::QpBackend`].

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
