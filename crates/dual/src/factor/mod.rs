//! The one factorisation of A every dual method shares: a sparse Cholesky with the contact DOFs
//! ordered last ([`trailing`]), wrapped as the generalised inverse A⁺ of [`inverse`] (fixed DOFs
//! of floating bodies removed).

mod inverse;
mod trailing;

pub use inverse::{StiffnessInverse, MAX_TRAILING};
