#!/bin/sh
# Rewrites the parameter tables of the component READMEs from the nodes' field tables
# (`NODE --help-params`), between the lines <!-- params:begin --> and <!-- params:end -->.
# The *_params_file tests fail while a README differs. Usage: tools/update_params_tables.sh [BUILD]
set -eu
build=${1:-build}
cd "$(dirname "$0")/.."
for pair in tracker:components/tracker/README.md \
            motion_controller:components/motion_controller/README.md \
            camera_server:components/camera_server/README.md \
            simulator:components/simulator/README.md \
            ball_detector:components/ball_detector/node/README.md; do
  node=${pair%%:*}
  readme=${pair#*:}
  table=$(mktemp)
  "$build/bin/$node" --help-params >"$table"
  awk -v table="$table" '
    /^<!-- params:begin -->$/ { print; while ((getline line < table) > 0) print line; skip = 1; next }
    /^<!-- params:end -->$/ { skip = 0 }
    !skip { print }' "$readme" >"$readme.new"
  mv "$readme.new" "$readme"
  rm -f "$table"
done
