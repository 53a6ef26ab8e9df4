#!/bin/bash
# Compares the circles of two builds of the P2P core bit for bit (see dump.cpp).
# usage: check.sh BASE_LIB_DIR NEW_LIB_DIR [OUT_DIR]
#   *_LIB_DIR: a build's lib/ folder (libsb_ball_detector_core.a and its dependencies)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${3:-$(mktemp -d)}
mkdir -p "$out"
for side in base new; do
  lib=$([ $side = base ] && echo "$1" || echo "$2")
  g++ -std=c++20 -O2 -w -I"$root/components" $(pkg-config --cflags opencv4) "$here/dump.cpp" \
    "$lib/libsb_ball_detector_core.a" "$lib/libsb_stereo_core.a" "$lib/libsb_common_util.a" \
    -lopencv_ximgproc -lopencv_calib3d -lopencv_features2d -lopencv_flann -lopencv_imgcodecs -lopencv_imgproc -lopencv_core -o "$out/dump_$side"
  "$out/dump_$side" "$root" "$root/../shared/data" > "$out/$side.txt"
done
lines=$(grep -c ' n=' "$out/base.txt")
circles=$(grep -c '^  ' "$out/base.txt" || true)
if cmp -s "$out/base.txt" "$out/new.txt"; then
  echo "identical: $lines detector calls, $circles circles ($out)"
else
  echo "DIFFERENT ($out):"
  diff "$out/base.txt" "$out/new.txt" | head -40
  exit 1
fi
