#!/usr/bin/env bash
# The report's 360-degree scan (section 3.4.1): castRaysScan(pos, [0 0 0], 3600, 200, 2*pi, pi/9)
# from a position near the middle vehicle of the demo scene.
#   BEAMTRACE=path/to/beamtrace OUT=dir examples/panorama.sh [extra scan options]
set -euo pipefail
BEAMTRACE=${BEAMTRACE:-build/beamtrace}
OUT=${OUT:-out/panorama}
"$BEAMTRACE" scan --demo --pattern scan --position -10,0,0.5 --orientation 0,0,0 \
  --width 3600 --height 200 --hfov 6.283185307179586 --vfov 0.3490658503988659 \
  --output "$OUT" "$@"
