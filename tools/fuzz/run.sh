#!/usr/bin/env bash
# tools/fuzz/run.sh TARGET SECONDS   fuzz one target (or "all", one after the other) for SECONDS
# Builds build-fuzz/ with clang, libFuzzer, ASan and UBSan (-DSB_FUZZ=ON) the first time, then
# runs build-fuzz/bin/fuzz_TARGET at nice 19 on tests/fuzz/corpus/TARGET. New inputs go to
# build-fuzz/fuzz-work/TARGET, crashes to build-fuzz/fuzz-artifacts/TARGET/ (add each one you
# fix to the corpus). Targets: mcap params_yaml scenario calibration frame_decode dds_samples.
# Environment: SB_FUZZ_BUILD_DIR (default build-fuzz), SB_FUZZ_JOBS (build jobs, default 2).
set -euo pipefail
root=$(cd "$(dirname "$(readlink -f "$0")")/../.." && pwd)
all_targets=(mcap params_yaml scenario calibration frame_decode dds_samples)

if [ $# -ne 2 ] || ! [[ "$2" =~ ^[0-9]+$ ]]; then
  echo "usage: tools/fuzz/run.sh TARGET|all SECONDS   (targets: ${all_targets[*]})" >&2
  exit 2
fi
if ! command -v clang++ >/dev/null; then
  echo "fuzz: clang++ not found (apt-get install clang libclang-rt-14-dev)" >&2
  exit 2
fi
targets=("$1")
[ "$1" = all ] && targets=("${all_targets[@]}")
for t in "${targets[@]}"; do
  if ! [[ " ${all_targets[*]} " == *" $t "* ]]; then
    echo "fuzz: unknown target '$t' (targets: ${all_targets[*]})" >&2
    exit 2
  fi
done

build=${SB_FUZZ_BUILD_DIR:-$root/build-fuzz}
if [ ! -f "$build/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DSB_FUZZ=ON >/dev/null
fi
nice cmake --build "$build" -j"${SB_FUZZ_JOBS:-2}" --target "${targets[@]/#/fuzz_}"

for t in "${targets[@]}"; do
  work="$build/fuzz-work/$t"
  artifacts="$build/fuzz-artifacts/$t"
  mkdir -p "$work" "$artifacts"
  echo "fuzz: $t for $2 s (corpus tests/fuzz/corpus/$t, crashes in $artifacts/)"
  nice -n 19 "$build/bin/fuzz_$t" -max_total_time="$2" -rss_limit_mb=2048 -timeout=10 \
    -print_final_stats=1 -artifact_prefix="$artifacts/" "$work" "$root/tests/fuzz/corpus/$t"
done
