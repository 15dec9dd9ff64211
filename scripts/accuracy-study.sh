#!/usr/bin/env bash
# Discretisation accuracy against time (issue 10): `signorini study` on the fixtures with an
# analytic [reference] (fixtures/accuracy/, Hertz from Johnson's formulas, the patch test's
# uniform pressure), for {node-to-segment, mortar} x {uniform, graded} x {p1, q1}.
#   * Hertz: --hmax sets both bodies' size; the graded scene's refine boxes (hmax 1/8 of the
#     bodies') scale with it: contact-zone sizes a/6.25 to a/50 (graded), bodies a/0.8 to
#     a/6.25 (uniform).  Q1 applies to the block only (the cap is not a rectangle).
#   * Patch test: non-matching 0.07 : 0.1 kept at every size; no refine box, so "graded" is
#     skipped (the study says so).
#   * Cattaneo-Mindlin (fixtures/accuracy/cattaneo.toml, the graded Hertz scene pressed then
#     shifted with Coulomb mu = 0.3): graded meshes, zone sizes a/4 to a/33 (a ~ 0.033 at this
#     press); stick half-width c and rms tangential traction error.
# Output: OUT/accuracy-hertz/, OUT/accuracy-patch/ and OUT/accuracy-cattaneo/, each with
# study.csv and accuracy.svg.
# Usage: scripts/accuracy-study.sh [OUT_DIR]      (a few minutes on 2 cores, release build)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out}
cargo build --release -q -p signorini
bin=target/release/signorini
status=0
# A study exits 2 when some point is not solved (it is still written, with its status).
study() { "$bin" study "$@" --overwrite || { rc=$?; [ $rc -eq 2 ] || exit $rc; status=2; }; }

study fixtures/accuracy/hertz-graded.toml --hmax 0.064,0.032,0.016,0.008 \
  --formulations node-to-segment,mortar --meshes uniform,graded --elements p1,q1 \
  --out "$out/accuracy-hertz"

study fixtures/accuracy/patch.toml --hmax 0.1,0.05,0.025,0.0125 \
  --formulations node-to-segment,mortar --meshes uniform,graded --elements p1,q1 \
  --out "$out/accuracy-patch"

study fixtures/accuracy/cattaneo.toml --hmax 0.064,0.032,0.016,0.008 \
  --formulations node-to-segment,mortar --meshes graded --elements p1 \
  --out "$out/accuracy-cattaneo"

for d in accuracy-hertz accuracy-patch accuracy-cattaneo; do
  echo "wrote $out/$d/study.csv and $out/$d/accuracy.svg"
done
[ $status -eq 0 ] || echo "warning: some points were not solved (see the tables above)" >&2
exit $status
