//! The suite as a table on the terminal.
