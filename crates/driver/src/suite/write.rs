//! The suite's files, written as one set.
