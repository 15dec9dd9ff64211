//! One module per subcommand: its handler, called by `main` with the parsed arguments.

pub(crate) mod check;
pub(crate) mod compare;
pub(crate) mod export;
pub(crate) mod qpset;
pub(crate) mod schema;
pub(crate) mod solve;
pub(crate) mod study;
pub(crate) mod suite;
pub(crate) mod sweep;
