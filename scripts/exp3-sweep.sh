#!/usr/bin/env bash
# Reproduces the seed's Experiment 3 (time vs mesh density) and carries it on to ~10^6 DOFs:
#   (a) refine body 2 ("lower") only, (b) refine both bodies; then a work–precision study.
# Every backend runs each point with a 120 s limit and is dropped on finer meshes once it
# exceeds it.  Output: out/exp3-{body2,both,precision}/ with sweep.csv and SVG plots.
# Usage: scripts/exp3-sweep.sh [OUT_DIR]       (takes about an hour on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out}
cargo build --release -q -p signorini
bin=target/release/signorini
# A sweep exits 2 when some point is not solved (a backend past its time limit on the finest
# meshes is expected here); anything else is an error.
sweep() { "$bin" sweep "$@" --overwrite || [ $? -eq 2 ]; }
# Body 1 ("upper") stays at the seed's hmax 0.2 in series (a); both start from 0.2 in (b).
body2=fixtures/seed/exp3-body2-h0.2.toml
both=fixtures/seed/exp3-both-h0.2.toml
backends=clarabel,osqp,dual-pgs,dual-uzawa,dual-ssn
seed_h=0.2,0.15,0.1,0.08

sweep "$body2" --bodies lower --hmax "$seed_h",0.04,0.02,0.01,0.005 \
  --backends "$backends" --tol 1e-8 --time-limit 120 --out "$out/exp3-body2"

sweep "$both" --hmax "$seed_h",0.04,0.02,0.01,0.007,0.005,0.0033 \
  --backends "$backends" --tol 1e-8 --time-limit 120 --out "$out/exp3-both"

sweep "$both" --hmax 0.02 --backends "$backends" \
  --tol 1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10 --time-limit 120 --out "$out/exp3-precision"
