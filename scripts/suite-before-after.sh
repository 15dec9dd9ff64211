#!/bin/sh
# Times two builds of signorini on the seed and hard suites, interleaved, three rounds, so that
# a reshaping can show it kept the speed (BENCHMARKS.md, "Reshaping without slowing down").
# usage (from the repository root): sh scripts/suite-before-after.sh OLD_BINARY NEW_BINARY OUT
# Each run's summary table (shifted geometric means, time and time ÷ floor) is in
# OUT/SUITE-old|new-ROUND.txt; compare the medians of the ÷ floor column.
set -eu
old=$1 new=$2 out=$3
mkdir -p "$out"
for round in 1 2 3; do
  for suite in seed hard; do
    "$old" suite "fixtures/$suite" --out "$out/$suite-old-$round" > "$out/$suite-old-$round.txt" 2>&1 || true
    "$new" suite "fixtures/$suite" --out "$out/$suite-new-$round" > "$out/$suite-new-$round.txt" 2>&1 || true
  done
done
echo "summaries in $out/*.txt"
