#!/usr/bin/env bash
# README command 1: install what is missing, build, and run the demo scan and the demo survey
# (a 64-beam scanner on a car in the embedded demo scene, written as LAS 1.4).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
# Only the CLI is built; the test and bench settings of an existing build/ are left as they are.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target beamtrace beamtrace_pushbroom_rays
./build/beamtrace scan --demo --output out/demo "$@"
./build/beamtrace survey examples/surveys/car_hdl64.yaml --output out/car_hdl64
./build/beamtrace info out/car_hdl64/points.las
