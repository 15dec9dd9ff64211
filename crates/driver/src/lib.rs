//! The `signorini` command-line driver: solve, compare, sweep, export and check a scene.
//!
//! The library half holds the steps of a run (each one function with one job) so that tests can
//! call them; `main.rs` only parses the command line.

pub mod auto;
pub mod backends;
pub mod check;
pub mod compare;
pub mod contract;
pub mod exit;
pub mod export;
pub mod outdir;
pub mod output;
pub mod plots;
pub mod qp_files;
pub mod run;
pub mod study;
pub mod suite;
pub mod sweep;
