//! The `signorini` command-line driver: solve, compare, sweep, study, suite, export and check.
//!
//! The library half holds the steps of a run (each one function with one job) so that tests can
//! call them; the binary (`src/bin/signorini/`) parses the command line in `main.rs` and hands
//! each subcommand to its handler in `commands/`.

pub mod backends;
/// `auto` lives with backend selection ([`backends::auto`]); re-exported under its old path.
pub use backends::auto;
pub mod check;
pub mod compare;
pub mod contract;
pub mod digest;
pub mod exit;
pub mod export;
pub mod fclib;
pub mod fclib_import;
pub use backends::guard;
pub mod outdir;
pub mod output;
pub mod plots;
pub mod qp_files;
pub mod qpset;
pub mod run;
pub mod study;
pub mod suite;
pub mod sweep;
