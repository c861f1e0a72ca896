#!/usr/bin/env bash
# Installs the Debian 12 packages beamtrace needs, only those that are missing.
set -euo pipefail
pkgs=(build-essential cmake libcli11-dev libpng-dev libtiff-dev libyaml-cpp-dev nlohmann-json3-dev
      libgtest-dev libbenchmark-dev libembree-dev
      # a compiler cache: scripts/test.sh's three builds reuse what an earlier run compiled
      ccache
      # the include check (scripts/check_includes.py, a ctest test)
      python3
      # view --interactive (GLFW/OpenGL) and its headless test (Xvfb); view --mp4 and its test
      libglfw3-dev xvfb xauth ffmpeg
      # surveys across MPI ranks (mpirun -n N beamtrace survey, docs/cluster.md) and their tests
      libopenmpi-dev openmpi-bin
      # the Python module (python/, docs/python.md) and its pytest suite
      pybind11-dev python3-dev python3-numpy python3-pytest
      # `pip install .` of the module (setup.py), offline, and its test (a venv)
      python3-pip python3-setuptools python3-wheel python3-venv)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node.js and npm run the independent LAS readers of the tests (npm packages, installed by the
# tests from the npm registry). A Node.js from elsewhere (it ships its own npm) is kept.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  for p in nodejs npm; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
fi
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
