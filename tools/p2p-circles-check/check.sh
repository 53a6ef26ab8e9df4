#!/bin/bash
# Compares the circles of two builds of the P2P core bit for bit (see dump.cpp).
# usage: check.sh BASE_LIB_DIR NEW_LIB_DIR [OUT_DIR]
#   *_LIB_DIR: a build's lib/ folder (libsb_ball_detector_core.a and its dependencies)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${3:-$(mktemp -d)}
mkdir -p "$out"
# Each library is compiled against its own checkout's headers (a struct that changed between
# the two would otherwise be read with the wrong layout): the checkout is the one its build's
# CMakeCache.txt names, else this one.
source_of() {
  local cache="$1/../CMakeCache.txt" src=""
  [ -f "$cache" ] && src=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$cache")
  [ -n "$src" ] && [ -d "$src/components" ] && echo "$src" || echo "$root"
}
for side in base new; do
  lib=$([ $side = base ] && echo "$1" || echo "$2")
  src=$(source_of "$lib")
  dump="$src/tools/p2p-circles-check/dump.cpp"
  [ -f "$dump" ] || dump="$here/dump.cpp"
  echo "$side: $lib with the headers of $src" >&2
  g++ -std=c++20 -O2 -w -I"$src/components" $(pkg-config --cflags opencv4) "$dump" \
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
