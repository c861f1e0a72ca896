#!/usr/bin/env bash
# The report's occlusion example (section 3.4.2): a pinhole camera 100 m east of the vehicle at
# the origin, 5 m up, looking west (yaw -pi) and slightly down; the occluding plane of the demo scene is faces 80180-80181,
# which --exclude-faces drops from points.ply (the range image still shows the plane).
#   BEAMTRACE=path/to/beamtrace OUT=dir examples/occlusion.sh [extra scan options]
set -euo pipefail
BEAMTRACE=${BEAMTRACE:-build/beamtrace}
OUT=${OUT:-out/occlusion}
"$BEAMTRACE" scan --demo --pattern pinhole --position 100,0,5 --orientation 0,-0.037,-3.141592653589793 \
  --width 500 --height 200 --hfov 0.11 --vfov 0.05 --exclude-faces 80180-80181 \
  --output "$OUT" "$@"
