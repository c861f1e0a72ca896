#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang (ASan + UBSan, folder build-fuzz/) and runs
# each on a copy of its seed corpus fuzz/corpus/<target>/ (docs/dev/fuzzing.md).
#
# usage: scripts/fuzz.sh [-t SECONDS | -r RUNS] [-k] [-j JOBS] [TARGET...]
#   -t SECONDS  run each target this long (default 60)
#   -r RUNS     run each target for this many inputs instead (-runs=RUNS)
#   -k          keep going after a finding (libFuzzer's fork mode, ignoring crashes, OOMs and
#               timeouts: each is saved and the run goes on; for targets with known findings)
#   -j JOBS     build jobs (default: nproc)
#   TARGET      las_reader laz_reader scene_yaml survey_yaml obj ply stl gltf geotiff ascii_grid
#               rays_csv trajectory_csv (default: all)
# Extra libFuzzer flags go in FUZZ_FLAGS (e.g. FUZZ_FLAGS="-max_len=4096"). New inputs found go
# to build-fuzz/corpus/<target>/ (not the repository); crash reproducers to
# build-fuzz/findings/<target>/. The harnesses' input files live in $FUZZ_TMPDIR (default
# /dev/shm: on a disk folder las_reader ran 3 times slower here). Exit status 1 if
# any target reported a finding (with -k: if any was saved).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=60 runs="" jobs=$(nproc) keep_going=()
while getopts "t:r:kj:" opt; do
  case $opt in
    t) seconds=$OPTARG ;;
    r) runs=$OPTARG ;;
    k) keep_going=(-fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1) ;;
    j) jobs=$OPTARG ;;
    *) sed -n '2,20p' "$0"; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
all="las_reader laz_reader scene_yaml survey_yaml obj ply stl gltf geotiff ascii_grid rays_csv trajectory_csv"
targets=${*:-$all}

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DBEAMTRACE_FUZZ=ON -DBEAMTRACE_BUILD_TESTS=OFF \
  -DBEAMTRACE_BUILD_BENCH=OFF -DBEAMTRACE_WITH_GLFW=OFF "${launcher[@]}" >/dev/null
for t in $targets; do build_targets+=("beamtrace_fuzz_$t"); done
cmake --build build-fuzz -j"$jobs" --target "${build_targets[@]}"

limit=(-max_total_time="$seconds")
[ -n "$runs" ] && limit=(-runs="$runs")
tmp=${FUZZ_TMPDIR:-/dev/shm}
[ -d "$tmp" ] && [ -w "$tmp" ] || tmp=${TMPDIR:-/tmp}
failed=""
for t in $targets; do
  corpus=build-fuzz/corpus/$t findings=build-fuzz/findings/$t
  mkdir -p "$corpus" "$findings"
  echo "== $t: ${limit[*]}"
  # Leaks are reported (detect_leaks=1); a finding stops the target, the others still run.
  before=$(find "$findings" -type f | wc -l)
  if ! TMPDIR=$tmp ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
       "build-fuzz/fuzz/beamtrace_fuzz_$t" "${limit[@]}" "${keep_going[@]}" -rss_limit_mb=2048 \
       -timeout=10 -artifact_prefix="$findings/" -print_final_stats=1 ${FUZZ_FLAGS:-} \
       "$corpus" "fuzz/corpus/$t" ||
     [ "$(find "$findings" -type f | wc -l)" != "$before" ]; then
    failed="$failed $t"
  fi
done
if [ -n "$failed" ]; then
  echo "fuzz.sh: findings in:$failed (reproducers in build-fuzz/findings/)" >&2
  exit 1
fi
echo "fuzz.sh: no findings"
