#!/usr/bin/env bash
# One entry point for a fresh Debian bookworm machine (run as root, or with sudo available):
#   bash run.sh demo [demo args...]   install what is missing, build, run the whole system
#                                     on the built-in simulator (stereoball demo)
#   bash run.sh test [ctest args...]  install what is missing, build, run the test suite (ctest);
#                                     fails when a test skipped that this machine could run
#   bash run.sh build                 install what is missing and build everything (no run)
# Builds go to build/, programs to build/bin/.
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")"

# What the programs are built from (every one is used by the build; V4L2 comes from the
# kernel headers in linux-libc-dev, idlc from cyclonedds-tools).
BUILD_PACKAGES=(
  build-essential cmake pkg-config linux-libc-dev
  cyclonedds-dev cyclonedds-tools
  libopencv-dev libopencv-contrib-dev libeigen3-dev libyaml-cpp-dev libcli11-dev libzstd-dev
  zlib1g-dev libjpeg-dev libsodium-dev
  # Small, header-only at configure time: the test targets are declared in every build,
  # even when only the demo's programs are compiled.
  libgtest-dev libgmock-dev nlohmann-json3-dev
  # stereoball view: WebSocket + HTTP server (header-only), TurboJPEG for the eyes.
  libwebsocketpp-dev libasio-dev libturbojpeg0-dev
)
# What only running the test suite needs: network namespaces (iproute2), Fast DDS + fastddsgen
# for the interop test, dpkg-dev + file for the package test. (clang + libclang-rt-14-dev are
# for tools/fuzz/run.sh only: the suite's GCC build replays the fuzz corpus without them.)
TEST_PACKAGES=(
  iproute2
  fastddsgen libfastrtps-dev libfastcdr-dev dpkg-dev file
  systemd  # systemd-analyze rates the units' sandbox in the package test
)

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else
    echo "run.sh: need root (or sudo) to install: $*" >&2; exit 1
  fi
}

install_missing() {
  local wanted=("${BUILD_PACKAGES[@]}")
  [ "${1:-}" = test ] && wanted+=("${TEST_PACKAGES[@]}")
  local missing=()
  for pkg in "${wanted[@]}"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
  done
  # Node.js runs the independent MCAP validator in the tests; any installed node/npm will do.
  if [ "${1:-}" = test ]; then
    command -v node >/dev/null || missing+=(nodejs)
    command -v npm >/dev/null || missing+=(npm)
    # A real browser loads the viewer page in the viewer tests.
    command -v chromium >/dev/null || missing+=(chromium)
  fi
  if [ ${#missing[@]} -gt 0 ]; then
    echo "run.sh: installing ${missing[*]}"
    as_root apt-get update -q
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
  fi
}

# build TARGET: configure and build TARGET (all, or demo_programs for the demo alone).
build() {
  local werror=OFF launcher=()
  [ "${CI:-}" = true ] && werror=ON
  # ccache, where the machine has it, makes rebuilds after a fresh clone cheap (not required).
  command -v ccache >/dev/null &&
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DSB_WERROR="$werror" -DSB_ONLY= \
    "${launcher[@]}" >/dev/null
  echo "run.sh: building $1 on $(nproc) cores into build/ (progress below)"
  cmake --build build -j"$(nproc)" --target "$1"
}

# A skipped test is accepted only when this machine lacks what it needs. Each check looks now
# (nothing is assumed): it prints what is missing and succeeds, or fails when it is there.
no_video_device() {
  compgen -G '/dev/video*' >/dev/null && return 1
  echo "no /dev/video* device"
}
no_namespaces() {
  local ns="sbskipcheck$$"
  if ip netns add "$ns" 2>/dev/null; then
    ip netns delete "$ns"
    return 1
  fi
  echo "network namespaces cannot be created here (root and iproute2 needed)"
}
no_netem() {
  no_namespaces && return 0
  local ns="sbskipcheck$$" found=1
  ip netns add "$ns" && ip -n "$ns" link set lo up &&
    ip netns exec "$ns" tc qdisc add dev lo root netem delay 1ms 2>/dev/null && found=0
  ip netns delete "$ns" 2>/dev/null || true
  [ "$found" -eq 0 ] && return 1
  echo "the kernel offers no netem qdisc (module sch_netem)"
}
roudi_running() {
  [ -S /tmp/roudi ] || return 1
  echo "an iceoryx RouDi runs here (/tmp/roudi)"
}
no_fuzz_build() {
  grep -q '^SB_FUZZ:BOOL=ON' CMakeCache.txt && return 1
  echo "not a clang build: libFuzzer needs one (tools/fuzz/run.sh)"
}
# The list: ctest entry -> the check of what it needs. Anything else that skips fails the run.
lacks_what_test_needs() {
  case "$1" in
    camera_server_device_test.needs_camera) no_video_device ;;
    distributed_test | rogue_host_test) no_namespaces ;;
    distributed_test.needs_netem) no_netem ;;
    common_shared_memory_test.needs_no_roudi) roudi_running ;;
    fuzz_libfuzzer) no_fuzz_build ;;
    *) return 1 ;;
  esac
}

# "NAME<TAB>reasons" for each test ctest skipped (SKIP_RETURN_CODE) in its JUnit file; the
# reasons are the test's "SKIP: ..." lines.
skipped_tests() {
  awk '
    function unxml(s) {
      gsub(/&lt;/, "<", s); gsub(/&gt;/, ">", s); gsub(/&quot;/, "\"", s); gsub(/&apos;/, "\047", s)
      gsub(/&amp;/, "\\&", s); return s
    }
    /<testcase / {
      match($0, /name="[^"]*"/); name = unxml(substr($0, RSTART + 6, RLENGTH - 7))
      skipped = 0; reasons = ""
    }
    /<skipped message="SKIP_RETURN_CODE=/ { skipped = 1 }
    /SKIP: / { r = substr($0, index($0, "SKIP: ") + 6); reasons = reasons (reasons == "" ? "" : "; ") unxml(r) }
    /<\/testcase>/ { if (skipped) print name "\t" (reasons == "" ? "(no reason printed)" : reasons) }
  ' "$1"
}

# Prints every skipped test with its reason; fails if one of them could have run here.
check_skips() {
  local name reasons lacks refused=0
  while IFS=$'\t' read -r name reasons; do
    if lacks=$(lacks_what_test_needs "$name"); then
      echo "run.sh: skipped $name: $reasons [accepted: $lacks]"
    else
      echo "run.sh: NOT ACCEPTED: $name skipped, but nothing it needs is missing here: $reasons" >&2
      refused=$((refused + 1))
    fi
  done < <(skipped_tests "$1")
  if [ "$refused" -gt 0 ]; then
    echo "run.sh: $refused test(s) skipped that this machine can run (list: lacks_what_test_needs in run.sh)" >&2
    return 1
  fi
}

case "${1:-}" in
  demo)
    install_missing demo
    build demo_programs
    shift
    exec build/bin/stereoball demo "$@"
    ;;
  test)
    install_missing test
    build all
    cd build
    shift
    status=0
    ctest --output-on-failure -j"$(nproc)" --timeout 900 --output-junit Testing/junit.xml "$@" ||
      status=$?
    check_skips Testing/junit.xml || status=1
    exit "$status"
    ;;
  build)
    install_missing test
    build all
    ;;
  *)
    echo "usage: bash run.sh demo|test|build" >&2
    exit 2
    ;;
esac
