#!/usr/bin/env bash
# No function longer than 80 lines in src/pipeline and apps/: clang-tidy's
# readability-function-size (its LineThreshold is in .clang-tidy), only that check, on every .cpp
# of those folders that the build compiles; fails on any warning. Not part of scripts/test.sh (it
# takes minutes).
#   scripts/check_function_size.sh [BUILD_DIR=build]
# Needs clang-tidy (apt install clang-tidy) and BUILD_DIR/compile_commands.json, which any
# configure writes (CMAKE_EXPORT_COMPILE_COMMANDS is on).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
if [ ! -f "$build/compile_commands.json" ]; then
  echo "check_function_size: no $build/compile_commands.json (configure first: cmake -S . -B $build)" >&2
  exit 2
fi
command -v clang-tidy >/dev/null || { echo "check_function_size: clang-tidy not found (apt install clang-tidy)" >&2; exit 2; }
# The files of src/pipeline and apps/ that the build compiles (view_window.cpp only with GLFW).
mapfile -t files < <(python3 - "$build/compile_commands.json" <<'PY'
import json, os, sys
root = os.getcwd()
for entry in json.load(open(sys.argv[1])):
    path = os.path.relpath(os.path.join(entry["directory"], entry["file"]), root)
    if path.endswith(".cpp") and path.startswith(("src/pipeline/", "apps/")):
        print(path)
PY
)
if [ ${#files[@]} -eq 0 ]; then
  echo "check_function_size: no src/pipeline or apps/ file in $build/compile_commands.json" >&2
  exit 2
fi
log=$(mktemp)
trap 'rm -f "$log"' EXIT
# GCC's warning flags that clang does not know are not errors here.
printf '%s\n' "${files[@]}" | sort -u |
  xargs -P "$(nproc)" -n 1 clang-tidy -p "$build" --quiet --checks='-*,readability-function-size' \
        --extra-arg=-Wno-unknown-warning-option >"$log" 2>/dev/null || true
if grep -qE ': (warning|error):' "$log"; then
  grep -E ': (warning|error|note):' "$log"
  echo "check_function_size: $(grep -cE ': (warning|error):' "$log") problem(s) in ${#files[@]} files" >&2
  exit 1
fi
echo "check_function_size: ${#files[@]} files, no function over the line threshold"
