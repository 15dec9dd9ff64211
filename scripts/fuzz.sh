#!/usr/bin/env bash
# Runs the scene fuzz harness (crates/driver/tests/fuzz.rs, test `fuzz_survey`) on N generated
# scenes without stopping at the first failure, and prints a summary: failing cases per property
# and each distinct kind of failure (none is muted).  One shrunk example scene per kind is
# printed to the log and, with DUMP_DIR, saved as a .toml file (its Gmsh files embedded) ready
# for crates/driver/tests/fuzz-cases/.
#
# Usage: scripts/fuzz.sh [N] [DUMP_DIR]      (N default 10000)
# The cases run in chunks of CHUNK (default 5000) cases, one process each, so that a case that
# never returns (abandoned after 30 s on a worker thread) costs at most its own chunk.
# Exit status: 0 when every case passed every property, 1 otherwise.
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-10000}
dump=${2:-}
chunk=${CHUNK:-5000}
if [ -n "$dump" ]; then
  mkdir -p "$dump"
  export FUZZ_DUMP
  FUZZ_DUMP=$(cd "$dump" && pwd)
fi
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
cargo build --release -q -p signorini --tests
left=$n
i=0
while [ "$left" -gt 0 ]; do
  this=$(( left < chunk ? left : chunk ))
  PROPTEST_CASES=$this cargo test --release -q -p signorini --test fuzz -- \
    --ignored --exact fuzz_survey --nocapture --test-threads 1 > "$logs/$i.log" 2>&1 || true
  left=$(( left - this ))
  i=$(( i + 1 ))
done
python3 - "$logs" <<'PY'
import glob, re, sys
cases = passed = 0
props, kinds, stopped = {}, {}, 0
for path in sorted(glob.glob(sys.argv[1] + "/*.log")):
    text = open(path, encoding="utf-8", errors="replace").read()
    m = re.search(r"fuzz survey: (\d+) cases in [\d.]+ s; (\d+) passed", text)
    if not m:
        print(f"chunk {path}: no summary (build or harness failure)\n" + text[-2000:])
        sys.exit(1)
    cases += int(m.group(1)); passed += int(m.group(2))
    stopped += "stopping early" in text
    for p, c in re.findall(r"^  (\S+) +(\d+) failing case", text, re.M):
        props[p] = props.get(p, 0) + int(c)
    section = text.split("kinds of failure:", 1)[1] if "kinds of failure:" in text else ""
    section = section.split("\n===", 1)[0]
    for c, k in re.findall(r"^ +(\d+) (\S.*)$", section, re.M):
        kinds[k] = kinds.get(k, 0) + int(c)
print(f"fuzz: {cases} cases, {passed} passed every property"
      + (f" ({stopped} chunk(s) stopped early on cases that never returned)" if stopped else ""))
for p, c in props.items():
    print(f"  {p:<24} {c:>8} failing case(s)")
print("kinds of failure:")
for k, c in sorted(kinds.items()):
    print(f"  {c:>8} {k}")
sys.exit(1 if kinds or passed < cases else 0)
PY
