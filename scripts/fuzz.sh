#!/usr/bin/env bash
# Runs the scene fuzz harness (crates/driver/tests/fuzz.rs) on N generated scenes without
# stopping at the first failure, and prints a summary: failing cases per property, each distinct
# kind of failure (known gaps marked *), and one shrunk example scene per kind.
# Usage: scripts/fuzz.sh [N] [DUMP_DIR]
#   N         number of cases (default 10000)
#   DUMP_DIR  where to save the shrunk examples as .toml (for tests/fuzz-cases/); optional
# Exit status: 0 when only known gaps (KNOWN_GAPS in fuzz.rs) failed, non-zero otherwise.
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-10000}
dump=${2:-}
if [ -n "$dump" ]; then
  mkdir -p "$dump"
  export FUZZ_DUMP
  FUZZ_DUMP=$(cd "$dump" && pwd)
fi
PROPTEST_CASES=$n cargo test --release -q -p signorini --test fuzz -- \
  --ignored --exact fuzz_survey --nocapture --test-threads 1
