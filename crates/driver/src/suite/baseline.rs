//! `--baseline OLD/suite.json`: which cases got slower, faster or changed status.
