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
#   QPSET_PEERS     qpsolvers names of the solvers qpbenchmark runs (default: every sparse one
#                   the virtualenv has), e.g. "clarabel osqp piqp proxqp qpalm scs"
#   QPSET_RUNTIME   time limit per solve, seconds, for qpbenchmark, its solvers and ours
#                   (default 10, qpbenchmark's)
#   QPSET_LARGE     empty (default): the scenes at their own sizes; DOFS: every scene refined to
#                   about DOFS unknowns (`signorini qpset --large DOFS`, e.g. 1000000)
#   QPSET_BACKENDS  comma-separated signorini backends of step 4 (default: every one compiled in)
#   SIGNORINI       the signorini binary (default: built with cargo build --release)
#
# Steps: 1. a virtualenv with qpbenchmark and each solver that installs (a failing one is
# reported and left out); 2. `signorini qpset DIRS --out OUT/set --force [--large DOFS]`; 3. qpbenchmark on the
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
large=${QPSET_LARGE:-}
backends=${QPSET_BACKENDS:-}
peers=${QPSET_PEERS:-}
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

# 2. The set (refined to QPSET_LARGE unknowns when set).
if [ -z "${SIGNORINI:-}" ]; then
    (cd "$here" && cargo build --release -p signorini)
    SIGNORINI="${CARGO_TARGET_DIR:-$here/target}/release/signorini"
fi
set --
if [ -n "$large" ]; then
    set -- --large "$large"
fi
# shellcheck disable=SC2086
"$SIGNORINI" qpset $dirs --out "$out/set" --force "$@"

# 3. qpbenchmark on it, at its standard settings (runtime limit QPSET_RUNTIME, 10 s by default).
# The set's module reads its time limit from QPSET_RUNTIME (qpbenchmark's own default is 10 s).
export QPSET_RUNTIME="$runtime"
for s in $settings_list; do
    # qpbenchmark writes its results file as it goes, then a report that needs every settings
    # of the test set to have been run (2.7.1 raises KeyError otherwise): not an error here.
    # One run per solver of QPSET_PEERS (qpbenchmark's `--solver`), or one for all of them.
    for p in ${peers:-all}; do
        set -- --settings "$s" --author signorini-qpset-peers
        if [ "$p" != all ]; then
            set -- "$@" --solver "$p"
        fi
        (cd "$out/set" && "$py" signorini_contact.py run "$@") ||
            echo "qpset-peers: qpbenchmark's own report failed after the $s run ($p; it needs every settings); its results are kept" >&2
    done
done

# 4. Our backends on the very same files, filed under the same settings names, which decide
# the run as they decide qpbenchmark's: `default` at our default tolerance (1e-9, relative),
# `high_accuracy` driven to qpbenchmark's absolute residuals of 1e-9 (our relative tolerance
# tightened until they are met; `signorini qpset --help`).
set --
if [ -n "$backends" ]; then
    set -- --backends "$backends"
fi
ours=""
for s in $settings_list; do
    "$SIGNORINI" qpset --solve "$out/set" --settings "$s" \
        --time-limit "$runtime" --out "$out/ours-$s.csv" "$@"
    ours="$ours $out/ours-$s.csv"
done

# 5. The report.
settings_csv=$(echo $settings_list | tr ' ' ',')
# shellcheck disable=SC2086
"$py" "$here/scripts/qpset-report.py" --peers "$out/set/results/qpbenchmark_results.csv" \
    --ours $ours --out "$out/report.md" --plot "$out/profile" --settings "$settings_csv" \
    --runtime "$runtime" \
    --header "FEM contact test set: $(ls "$out/set/data" | wc -l) problems${large:+, refined to about $large unknowns}; $(date -u +%Y-%m-%d); $(nproc) cores; qpbenchmark $("$py" -c 'import qpbenchmark; print(qpbenchmark.__version__)')."
echo "qpset-peers: wrote $out/report.md and $out/profile-*.svg"
