//! Primal–dual active-set QP backend of signorini on the sparse primal KKT system.
//!
//! (Documentation of the method and its measurements: being written.)

mod active_set;
mod backend;
mod dense;
mod error;
mod factor;
mod kernel;
mod kkt;
mod refine;
mod settings;
mod update;

pub use backend::PdasBackend;
pub use error::PdasError;
pub use settings::{PdasSettings, StartSet};
