#!/usr/bin/env bash
# README command 1: install what is missing, build, and run the demo scan.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DBEAMTRACE_BUILD_TESTS=OFF -DBEAMTRACE_BUILD_BENCH=OFF >/dev/null
cmake --build build -j"$(nproc)" --target beamtrace
./build/beamtrace scan --demo --output out/demo "$@"
