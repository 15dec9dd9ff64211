#!/usr/bin/env bash
# Times every seed fixture through `signorini solve` (release build) and prints a Markdown table
# of mesh / assemble / solve / total times, the median of REPEAT runs (default 5).
# Usage: scripts/fixture-timings.sh [BACKEND] [REPEAT]
set -euo pipefail
cd "$(dirname "$0")/.."
backend=${1:-clarabel}
repeat=${2:-5}
cargo build --release -q -p signorini
bin=target/release/signorini
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "| fixture | DOFs | rows | active | iterations | mesh ms | assemble ms | solve ms | total ms | status |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|"
for scene in fixtures/seed/*.toml; do
  name=$(basename "$scene" .toml)
  for i in $(seq "$repeat"); do
    "$bin" solve "$scene" --backend "$backend" --out "$work/$name-$i" > /dev/null
  done
  python3 - "$work" "$name" "$repeat" <<'PY'
import json, statistics, sys
work, name, repeat = sys.argv[1], sys.argv[2], int(sys.argv[3])
runs = [json.load(open(f"{work}/{name}-{i}/result.json")) for i in range(1, repeat + 1)]
med = lambda k: statistics.median(r["timing_s"][k] for r in runs) * 1e3
r = runs[0]
print(f"| {name} | {r['dofs']} | {r['constraints']} | {r['active_constraints']} | {r['iterations']} "
      f"| {med('mesh'):.2f} | {med('assemble'):.2f} | {med('solve'):.2f} | {med('total'):.2f} | {r['status']} |")
PY
done
