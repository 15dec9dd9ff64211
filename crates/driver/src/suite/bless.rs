//! `--bless`: expectations written from the most accurate answer.
