#!/usr/bin/env bash
# Long-interface sweep (issue 9, item 6): time and peak memory of every backend on strip scenes
# (scripts/strip-scene.sh: a thin strip pressed along its whole length onto a foundation
# clamped at its bottom, every contact row active), in two series:
#   (a) m, the number of contact rows, from 10^3 to 4*10^4 at roughly fixed DOFs: the strip's
#       length L = (m-1)*hmax grows while the foundation gets thinner (the strip stays
#       --strip-layers elements thick), so that DOFs ~ 3.2 m (NS + NF + 2) stays near
#       --target-dofs (3.2 DOFs per row and layer of nodes: measured on these meshes);
#   (b) DOFs at fixed m (--fixed-m rows): the foundation's thickness grows through
#       --foundation-layers.
# Each (scene, backend) is one `signorini compare --backends B` run under /usr/bin/time -v, so
# its peak RSS is that backend's (together with the mesh, the assembly and the floor's
# factorisation, which compare times in the same process); `signorini check` is run once per
# scene and gives the DOFs and rows even when every backend is skipped, and its peak RSS (the
# backend "check" row: meshing and assembly only) is the baseline of the memory figures.
# A backend that does not finish within the time limit (status time-limit, killed by the outer
# timeout, or refused for memory) is skipped on the later, larger points of the same series.
#
# Output: OUT_DIR/long-interface.csv, rewritten whole (temporary file, then rename) after every
# point, with the columns
#   series,m,dofs,length,strip_layers,foundation_layers,backend,status,iterations,solve_s,
#   floor_s,ratio_to_floor,peak_rss_mb,exit_code,scene
# and OUT_DIR/scenes/*.toml, OUT_DIR/runs/<point>-<backend>/ (compare.json, compare.csv,
# time.txt, stderr.txt).
#
# Usage: scripts/long-interface-sweep.sh OUT_DIR [options]
#   --series a|b|ab          which series (default ab)
#   --m LIST                 series (a) rows (default 1001,2001,5001,10001,20001,40001)
#   --target-dofs N          series (a) DOFs (default 800000)
#   --fixed-m M              series (b) rows (default 2001: the issue's 20 x 0.02 strip)
#   --foundation-layers LIST series (b) foundation layers (default 2,4,8,16,32,64,128,256)
#   --strip-layers NS        strip thickness in elements (default 2: thin)
#   --support floating|clamped (default floating)
#   --hmax H                 (default 0.01)
#   --backends LIST          (default clarabel,osqp,dual-pgs,dual-uzawa,dual-ssn; add pdas or
#                            others as the binary offers them)
#   --tol T                  (default 1e-8, the issue's goal)
#   --time-limit S           seconds per backend (default 120, as scripts/exp3-sweep.sh)
# The full default sweep takes hours on 2 cores. A smoke run (about a minute):
#   scripts/long-interface-sweep.sh /tmp/li-smoke --m 1001 --target-dofs 40000 \
#     --fixed-m 1001 --foundation-layers 2,6 --time-limit 20
set -euo pipefail
cd "$(dirname "$0")/.."

usage() {
  sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//' >&2
  exit 1
}
[ $# -ge 1 ] || usage
case $1 in -*) usage ;; esac
out=$1
shift

series=ab
m_list=1001,2001,5001,10001,20001,40001
target_dofs=800000
fixed_m=2001
nf_list=2,4,8,16,32,64,128,256
ns=2
support=floating
hmax=0.01
backends=clarabel,osqp,dual-pgs,dual-uzawa,dual-ssn
tol=1e-8
limit=120
while [ $# -gt 0 ]; do
  [ $# -ge 2 ] || usage
  case $1 in
    --series) series=$2 ;;
    --m) m_list=$2 ;;
    --target-dofs) target_dofs=$2 ;;
    --fixed-m) fixed_m=$2 ;;
    --foundation-layers) nf_list=$2 ;;
    --strip-layers) ns=$2 ;;
    --support) support=$2 ;;
    --hmax) hmax=$2 ;;
    --backends) backends=$2 ;;
    --tol) tol=$2 ;;
    --time-limit) limit=$2 ;;
    *) usage ;;
  esac
  shift 2
done
case $series in a | b | ab) ;; *) usage ;; esac

cargo build --release -q -p signorini
bin=$PWD/target/release/signorini
mkdir -p "$out/scenes" "$out/runs"
csv=$out/long-interface.csv
rows=$out/.long-interface.rows
header=series,m,dofs,length,strip_layers,foundation_layers,backend,status,iterations,solve_s,floor_s,ratio_to_floor,peak_rss_mb,exit_code,scene
: > "$rows"

publish() {
  local tmp
  tmp=$(mktemp "$out/.long-interface.csv.XXXXXX")
  { echo "$header"; cat "$rows"; } > "$tmp"
  mv -f "$tmp" "$csv"
}

# Peak RSS in MB from a /usr/bin/time -v report ("" when absent).
peak_mb() {
  awk -F: '/Maximum resident set size/ { gsub(/ /, "", $2); printf "%.1f", $2 / 1024 }' "$1" 2>/dev/null || true
}

# A column of the one data row of a compare.csv, by header name ("" when absent).
csv_field() {
  awk -F, -v name="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == name) c = i; next }
    NR == 2 && c { print $c }' "$1" 2>/dev/null || true
}

# The outer guard: the backend's own limit, plus the mesh, assembly and floor, plus slack.
guard=$((limit * 2 + 600))

# run_point SERIES M NF: one scene, every backend not yet dropped from SERIES.
run_point() {
  local s=$1 m=$2 nf=$3
  local length name scene dofs check_rss b dir rc status
  length=$(awk -v m="$m" -v h="$hmax" 'BEGIN { printf "%.12g", (m - 1) * h }')
  name=$s-m$m-ns$ns-nf$nf-$support
  scene=$out/scenes/$name.toml
  scripts/strip-scene.sh --length "$length" --hmax "$hmax" --strip-layers "$ns" \
    --foundation-layers "$nf" --support "$support" > "$scene"
  mkdir -p "$out/runs/$name-check"
  rc=0
  /usr/bin/time -v -o "$out/runs/$name-check/time.txt" "$bin" check "$scene" \
    > "$out/runs/$name-check/stdout.txt" 2> "$out/runs/$name-check/stderr.txt" || rc=$?
  dofs=$(sed -n 's/.* \([0-9]*\) free DOFs.*/\1/p' "$out/runs/$name-check/stdout.txt")
  check_rss=$(peak_mb "$out/runs/$name-check/time.txt")
  status=valid
  [ "$rc" -eq 0 ] || status=refused
  echo "$s,$m,$dofs,$length,$ns,$nf,check,$status,,,,,$check_rss,$rc,$scene" >> "$rows"
  echo "[$s] m $m, foundation $nf layers: $dofs DOFs (check: $status, $check_rss MB)" >&2
  for b in ${backends//,/ }; do
    if grep -qx "$s:$b" "$out/.dropped" 2>/dev/null; then
      echo "$s,$m,$dofs,$length,$ns,$nf,$b,skipped,,,,,,,$scene" >> "$rows"
      continue
    fi
    dir=$out/runs/$name-$b
    mkdir -p "$dir"
    rm -f "$dir/compare.csv"
    rc=0
    # time(1) outside timeout(1): its report covers timeout's reaped child, signorini.
    /usr/bin/time -v -o "$dir/time.txt" timeout "$guard" "$bin" compare "$scene" \
      --backends "$b" --tol "$tol" --time-limit "$limit" --out "$dir" \
      > /dev/null 2> "$dir/stderr.txt" || rc=$?
    if [ -s "$dir/compare.csv" ] && [ "$rc" -le 2 ]; then
      status=$(csv_field "$dir/compare.csv" status)
    elif [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; then
      status=killed
    elif [ "$rc" -eq 3 ]; then
      status=refused
    else
      status=error
    fi
    local it solve floor ratio rss
    it=$(csv_field "$dir/compare.csv" iterations)
    solve=$(csv_field "$dir/compare.csv" solve_s)
    floor=$(csv_field "$dir/compare.csv" floor_s)
    ratio=$(csv_field "$dir/compare.csv" ratio_to_floor)
    rss=$(peak_mb "$dir/time.txt")
    echo "$s,$m,$dofs,$length,$ns,$nf,$b,$status,$it,$solve,$floor,$ratio,$rss,$rc,$scene" >> "$rows"
    echo "  $b: $status (exit $rc)" >&2
    case $status in
      time-limit | killed | refused | error) echo "$s:$b" >> "$out/.dropped" ;;
    esac
  done
  publish
}

rm -f "$out/.dropped"
if [ "$series" != b ]; then
  for m in ${m_list//,/ }; do
    nf=$(awk -v d="$target_dofs" -v m="$m" -v ns="$ns" \
      'BEGIN { n = int(d / (3.2 * m) - ns - 2 + 0.5); print (n < 1 ? 1 : n) }')
    run_point a "$m" "$nf"
  done
fi
if [ "$series" != a ]; then
  for nf in ${nf_list//,/ }; do
    run_point b "$fixed_m" "$nf"
  done
fi
publish
rm -f "$out/.dropped" "$rows"
echo "wrote $csv" >&2
