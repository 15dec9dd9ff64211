#!/bin/sh
# qpset-peers.sh: the FEM contact test set (`signorini qpset`) through qpbenchmark's Python QP
# solvers and through every signorini backend, side by side (docs/qp-benchmark.md).
#
# Usage: scripts/qpset-peers.sh [OUT]          (default OUT = qpset-run)
# Environment:
#   QPSET_DIRS      scene directories of the set (default: the seed, hard, accuracy and qpset
#                   fixtures)
#   QPSET_SETTINGS  qpbenchmark settings to run (default: "default high_accuracy")
#   QPSET_VENV      virtualenv to create/use (default: OUT/venv)
#   QPSET_SOLVERS   pip packages of the solvers (default: every open one qpbenchmark drives)
#   QPSET_RUNTIME   time limit per solve, seconds (default 10, qpbenchmark's)
#   SIGNORINI       the signorini binary (default: built with cargo build --release)
#
# Steps: 1. a virtualenv with qpbenchmark and each solver that installs (a failing one is
# reported and left out); 2. `signorini qpset DIRS --out OUT/set --force`; 3. qpbenchmark on the
# set at each settings (`python OUT/set/signorini_contact.py run --settings S`); 4. our backends
# on the same .npz files (`signorini qpset --solve OUT/set`), rows in qpbenchmark's columns;
# 5. scripts/qpset-report.py: OUT/report.md and OUT/profile-SETTINGS.svg.
set -eu

here=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-qpset-run}
mkdir -p "$out"
out=$(cd "$out" && pwd)
dirs=${QPSET_DIRS:-"$here/fixtures/seed $here/fixtures/hard $here/fixtures/accuracy $here/fixtures/qpset"}
settings_list=${QPSET_SETTINGS:-"default high_accuracy"}
venv=${QPSET_VENV:-$out/venv}
runtime=${QPSET_RUNTIME:-10}
solvers=${QPSET_SOLVERS:-"clarabel osqp piqp proxsuite daqp highspy scs cvxopt quadprog qpalm ecos kvxopt"}

# 1. Python side.
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
py="$venv/bin/python"
"$py" -m pip install -q qpbenchmark
for s in $solvers; do
    "$py" -m pip install -q "$s" >/dev/null 2>&1 || echo "qpset-peers: $s does not install here; left out" >&2
done
"$py" -c 'import qpsolvers; print("qpsolvers sparse solvers available:", sorted(qpsolvers.sparse_solvers))'

# 2. The set.
if [ -z "${SIGNORINI:-}" ]; then
    (cd "$here" && cargo build --release -p signorini)
    SIGNORINI="${CARGO_TARGET_DIR:-$here/target}/release/signorini"
fi
# shellcheck disable=SC2086
"$SIGNORINI" qpset $dirs --out "$out/set" --force

# 3. qpbenchmark on it, at its standard settings (runtime limit: the set's, 10 s by default).
for s in $settings_list; do
    # qpbenchmark writes its results file as it goes, then a report that needs every settings
    # of the test set to have been run (2.7.1 raises KeyError otherwise): not an error here.
    (cd "$out/set" && "$py" signorini_contact.py run --settings "$s" --author signorini-qpset-peers) ||
        echo "qpset-peers: qpbenchmark's own report failed after the $s run (it needs every settings); its results are kept" >&2
done

# 4. Our backends on the very same files, filed under the same settings names, which decide
# the run as they decide qpbenchmark's: `default` at our default tolerance (1e-9, relative),
# `high_accuracy` driven to qpbenchmark's absolute residuals of 1e-9 (our relative tolerance
# tightened until they are met; `signorini qpset --help`).
ours=""
for s in $settings_list; do
    "$SIGNORINI" qpset --solve "$out/set" --settings "$s" \
        --time-limit "$runtime" --out "$out/ours-$s.csv"
    ours="$ours $out/ours-$s.csv"
done

# 5. The report.
settings_csv=$(echo $settings_list | tr ' ' ',')
# shellcheck disable=SC2086
"$py" "$here/scripts/qpset-report.py" --peers "$out/set/results/qpbenchmark_results.csv" \
    --ours $ours --out "$out/report.md" --plot "$out/profile" --settings "$settings_csv" \
    --runtime "$runtime" \
    --header "FEM contact test set: $(ls "$out/set/data" | wc -l) problems; $(date -u +%Y-%m-%d); $(nproc) cores; qpbenchmark $("$py" -c 'import qpbenchmark; print(qpbenchmark.__version__)')."
echo "qpset-peers: wrote $out/report.md and $out/profile-*.svg"
