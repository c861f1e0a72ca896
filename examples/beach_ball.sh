#!/usr/bin/env bash
# Renders the assignment's beach ball: a pinhole view with its shadow, and an orthographic
# top view. Usage: examples/beach_ball.sh [path/to/beamtrace] [output-dir]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
bin="${1:-$here/../build/beamtrace}"
out="${2:-.}"
mkdir -p "$out"
"$bin" render "$here/scenes/beach_ball.yaml" --camera -6,-4,3,0,0,40 --look-at 0,0,0.8 \
    --light dir:-60,45,0.9 --ambient 0.15 --size 640x480 --gamma 2.2 --sky \
    --output "$out/beach_ball.png"
"$bin" render "$here/scenes/beach_ball.yaml" --camera 0,0,10,0,-90 --orthographic 6 \
    --light dir:-60,45 --size 400x400 --output "$out/beach_ball_top.png"
