#!/usr/bin/env bash
# The report's push-broom example (section 3.4.3): 500 lines of a 1 x 500 pinhole on a rolling
# platform, written as a rays file by examples/pushbroom_rays.cpp, then traced as one ray list and
# shown as a 500 x 500 range image.
#   BEAMTRACE=... PUSHBROOM_RAYS=path/to/beamtrace_pushbroom_rays OUT=dir examples/pushbroom.sh
set -euo pipefail
BEAMTRACE=${BEAMTRACE:-build/beamtrace}
PUSHBROOM_RAYS=${PUSHBROOM_RAYS:-build/beamtrace_pushbroom_rays}
OUT=${OUT:-out/pushbroom}
mkdir -p "$OUT"
"$PUSHBROOM_RAYS" "$OUT/pushbroom_rays.csv" 500 200
"$BEAMTRACE" scan --demo --pattern rays --rays "$OUT/pushbroom_rays.csv" --width 500 --height 500 \
  --output "$OUT" "$@"
