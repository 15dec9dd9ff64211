#!/usr/bin/env bash
# The default backend against the fastest one, fixture by fixture (issue 9: "the default
# backend within 1.5× of the fastest on every fixture and hard case").  Every seed and hard
# fixture is compared REPEAT times (default 3) with every backend and `auto`; per backend the
# fastest of its solved runs counts.  Prints a Markdown table: the fastest backend and its solve
# time, auto's solve time and what auto chose, and auto ÷ fastest.  A fixture that no backend
# solves (floating-free: dual-infeasible for all) is listed with its statuses.
# Usage: scripts/auto-vs-fastest.sh [REPEAT] [TIME_LIMIT_S]
set -euo pipefail
cd "$(dirname "$0")/.."
repeat=${1:-3}
limit=${2:-10}
cargo build --release -q -p signorini
bin=$PWD/target/release/signorini
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
backends=clarabel,osqp,dual-pgs,dual-uzawa,pdas,dual-ssn,auto
for scene in fixtures/seed/*.toml fixtures/hard/*.toml; do
  name=$(basename "$(dirname "$scene")")/$(basename "$scene" .toml)
  for i in $(seq "$repeat"); do
    # Exit 2 (some backend not solved) is expected; a scene without contact rows (inert-rows)
    # has nothing to compare (exit 1) and is skipped; anything else is an error.
    code=0
    "$bin" compare "$scene" --backends "$backends" --time-limit "$limit" \
      --out "$work/${name//\//-}-$i" > /dev/null 2> "$work/stderr" || code=$?
    if [ "$code" -eq 1 ] && grep -q "no contact constraint row" "$work/stderr"; then
      break
    fi
    [ "$code" -eq 0 ] || [ "$code" -eq 2 ] || { cat "$work/stderr" >&2; exit "$code"; }
  done
done
python3 - "$work" "$repeat" <<'PY'
import glob, json, os, sys
work, repeat = sys.argv[1], int(sys.argv[2])
runs = {}
for path in sorted(glob.glob(f"{work}/*/compare.json")):
    key = os.path.basename(os.path.dirname(path)).rsplit("-", 1)[0]
    runs.setdefault(key, []).append(json.load(open(path)))
print("| fixture | DOFs | rows | fastest | its solve ms | auto ms | auto chose | auto ÷ fastest |")
print("|---|---:|---:|---|---:|---:|---|---:|")
worst = 0.0
for key, reports in runs.items():
    best = {}
    chose = "?"
    for rep in reports:
        for row in rep["backends"]:
            if row["status"] != "solved":
                continue
            b = row["backend"]
            best[b] = min(best.get(b, float("inf")), row["solve_s"])
            if b == "auto":
                chose = (row.get("message") or "").split(";")[0].replace("auto: ", "")
    others = {b: t for b, t in best.items() if b != "auto"}
    r = reports[0]
    if not others:
        statuses = ", ".join(f"{x['backend']} {x['status']}" for x in r["backends"])
        print(f"| {key} | {r['dofs']} | {r['constraints']} | none solved ({statuses}) | | | | |")
        continue
    fastest = min(others, key=others.get)
    auto = best.get("auto", float("nan"))
    ratio = auto / others[fastest]
    worst = max(worst, ratio) if ratio == ratio else float("inf")
    print(f"| {key} | {r['dofs']} | {r['constraints']} | {fastest} | {others[fastest]*1e3:.2f} "
          f"| {auto*1e3:.2f} | {chose} | {ratio:.2f} |")
print(f"\nworst auto ÷ fastest: {worst:.2f} (best of {repeat} runs per backend)")
PY
