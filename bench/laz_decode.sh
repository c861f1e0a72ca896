#!/usr/bin/env bash
# LAZ decode rates in one run: our LasReader at 1 and 2 threads (beamtrace_bench BM_LazDecode)
# beside laz-perf (lasval's copc.js, wasm, one thread) on the same files, as a Markdown table
# with the ratio to laz-perf. Needs a Release build with benchmarks (build/bench/beamtrace_bench)
# and Node with lasval's npm packages (the tests install them in build/lasval-cache).
# usage: bench/laz_decode.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
lasval=$build/lasval-cache
data=$(sed -n 's/^BEAMTRACE_SHARED_DATA_DIR:[A-Z]*=//p' "$build/CMakeCache.txt")
[ -n "$data" ] || data=../shared/data
[ -d "$lasval/node_modules" ] || { echo "no $lasval/node_modules: run the LAZ tests first" >&2; exit 2; }
cp bench/laz/lasperf_decode.mjs "$lasval/"
ours=$("$build/bench/beamtrace_bench" --benchmark_filter=BM_LazDecode --benchmark_format=csv 2>/dev/null)
files=$(echo "$ours" | sed -n 's/.*"\([^"]*\.laz\)".*/\1/p' | sort -u)
theirs=$(cd "$lasval" && for f in $files; do node lasperf_decode.mjs "$data/las/laz/$f"; done)
echo "| file | points | laz-perf M pts/s | ours 1 thread | ours 2 threads | 2 threads / laz-perf |"
echo "|---|---:|---:|---:|---:|---:|"
for f in $files; do
  lp=$(echo "$theirs" | awk -v f="$f" '$1 ~ f"$" {print $3}')
  n=$(echo "$theirs" | awk -v f="$f" '$1 ~ f"$" {print $2}')
  r1=$(echo "$ours" | awk -F, -v f="\"$f\"" '$0 ~ "threads:1/" && index($0, f) {print $NF}' | head -1)
  r2=$(echo "$ours" | awk -F, -v f="\"$f\"" '$0 ~ "threads:2/" && index($0, f) {print $NF}' | head -1)
  awk -v f="$f" -v n="$n" -v lp="$lp" -v r1="$r1" -v r2="$r2" 'BEGIN {
    printf "| %s | %d | %.2f | %.2f | %.2f | %.2fx |\n", f, n, lp / 1e6, r1 / 1e6, r2 / 1e6, r2 / lp }'
done
