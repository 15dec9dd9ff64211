#!/usr/bin/env bash
# Runs one sweep as N shards on this machine, then merges them: the shards with GNU parallel
# when it is installed (JOBS of them at a time, default: one per core), else one after another.
# On a cluster, run the same shard commands as a Slurm job array instead (docs/scene.md, "sweep
# across machines"); this script is only the local equivalent, not a scheduler.
#
# Usage: scripts/sweep-shards.sh N OUT_DIR SCENE [sweep options...]
#   e.g. scripts/sweep-shards.sh 4 out/exp3 fixtures/seed/exp3-both-h0.2.toml \
#          --hmax 0.2,0.1,0.05,0.02 --backends clarabel,dual-pgs --tol 1e-8
# Shard I writes OUT_DIR/shard-I (add --resume to finish shards an earlier run left
# incomplete, --overwrite to redo them); the merged sweep.csv and plots go to OUT_DIR/merged.
# Environment: SIGNORINI=path of the binary (default: build target/release/signorini),
# JOBS=shards run at once by GNU parallel.
# Exit code: the merge's (0 all solved, 2 some point not solved or skipped, 1 a shard missing,
# incomplete or not of this sweep, 3 I/O).
set -euo pipefail
if [[ $# -lt 3 ]]; then
  sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 1
fi
n=$1
out=$2
shift 2
if ! [[ $n =~ ^[1-9][0-9]*$ ]]; then
  echo "sweep-shards: N must be a positive integer, got '$n'" >&2
  exit 1
fi
if [[ -n ${SIGNORINI:-} ]]; then
  bin=$SIGNORINI
else
  root=$(cd "$(dirname "$0")/.." && pwd)
  (cd "$root" && cargo build --release -q -p signorini)
  bin=$root/target/release/signorini
fi
mkdir -p "$out"

# A shard that exits non-zero (2: some point not solved) is not an error here: the merge checks
# that every shard finished (its shard.json says "complete") and refuses otherwise.
if command -v parallel >/dev/null 2>&1; then
  seq 1 "$n" | parallel -q -j "${JOBS:-100%}" --line-buffer --tagstring 'shard {}/'"$n" \
    "$bin" sweep "$@" --shard "{}/$n" --out "$out/shard-{}" || true
else
  echo "sweep-shards: GNU parallel not found, running the $n shards one after another" >&2
  for i in $(seq 1 "$n"); do
    "$bin" sweep "$@" --shard "$i/$n" --out "$out/shard-$i" || true
  done
fi

dirs=()
for i in $(seq 1 "$n"); do dirs+=("$out/shard-$i"); done
exec "$bin" sweep merge "${dirs[@]}" --out "$out/merged" --overwrite
