#!/usr/bin/env bash
# The threaded tests under ThreadSanitizer: the ball detector's task helper (in the test and in
# the ball_detector process), the camera_server capture thread and preview worker, the viewer
# (stereoball-view and the tests' preview publisher). Builds only their targets in BUILD_DIR
# (configured with -DSB_SANITIZE=thread; niced), runs them, and fails when a test fails or any
# process wrote a race report (BUILD_DIR/tsan/report.<pid>, printed here).
#   tools/tsan_tests.sh [BUILD_DIR]      (default build-tsan)
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/.."
dir=${1:-build-tsan}
grep -q '^SB_SANITIZE:.*=thread$' "$dir/CMakeCache.txt" || {
  echo "tsan_tests.sh: $dir is not a -DSB_SANITIZE=thread build" >&2
  exit 2
}
tests=(sb_ball_detector_node_lib_test ball_detector_node_test camera_server_capture_test camera_server_node_test
  stereo_frame_preview_test viewer_core_test viewer_bridge_test viewer_flow_test
  viewer_bad_input_test)
programs=(ball_detector camera_server stereoball-view)
nice cmake --build "$dir" -j2 --target "${tests[@]}" "${programs[@]}"
mkdir -p "$dir/tsan"
rm -f "$dir"/tsan/report.*
status=0
ctest --test-dir "$dir" -R "^($(IFS='|' && echo "${tests[*]}"))\$" --output-on-failure \
  --timeout 900 || status=$?
shopt -s nullglob
reports=("$dir"/tsan/report.*)
for r in "${reports[@]}"; do
  echo "=== $r"
  cat "$r"
done
if [ ${#reports[@]} -gt 0 ]; then
  echo "tsan_tests.sh: ${#reports[@]} process(es) reported races (above)" >&2
  status=1
fi
exit "$status"
