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
  build-essential cmake ninja-build pkg-config linux-libc-dev
  cyclonedds-dev cyclonedds-tools
  libopencv-dev libopencv-contrib-dev libeigen3-dev libyaml-cpp-dev libcli11-dev libzstd-dev
  zlib1g-dev libjpeg-dev libsodium-dev
  # Small, header-only at configure time: the test targets are declared in every build,
  # even when only the demo's programs are compiled.
  libgtest-dev libgmock-dev nlohmann-json3-dev
  # stereoball view: WebSocket + HTTP server (header-only), TurboJPEG for the eyes.
  libwebsocketpp-dev libasio-dev libturbojpeg0-dev
)
# What only running the test suite needs. Found when the build is configured: Fast DDS +
# fastddsgen for the interop test, dpkg-dev for the package test. (clang + libclang-rt-14-dev
# are for tools/fuzz/run.sh only: the suite's GCC build replays the fuzz corpus without them.)
TEST_PACKAGES=(fastddsgen libfastrtps-dev libfastcdr-dev dpkg-dev)
# Needed only when the tests run: network namespaces (iproute2), `file` for cpack in the
# package test, systemd-analyze rating the units' sandbox there; Node.js, npm and Chromium
# (added below when missing) for the viewer and MCAP tests. They are installed in the
# background while the build compiles, and the npm packages the tests use are fetched into
# npm's cache then (the tests install them from it, offline).
TEST_RUN_PACKAGES=(iproute2 file systemd)

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else
    echo "run.sh: need root (or sudo) to install: $*" >&2; exit 1
  fi
}

# missing_of PKG...: those not installed.
missing_of() {
  local pkg
  for pkg in "$@"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || echo "$pkg"
  done
}

apt_install() {
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "$@"
}

# Fills npm's cache with the packages of the tests' package-lock.json files.
npm_cache_warm() {
  local lock dir
  for lock in tests/viewer/package-lock.json tests/mcap_validator/package-lock.json; do
    dir=$(mktemp -d)
    cp "$(dirname "$lock")/package.json" "$lock" "$dir/"
    (cd "$dir" && npm ci --ignore-scripts --no-audit --no-fund --prefer-offline >/dev/null) ||
      echo "run.sh: npm could not fetch the packages of $lock (the tests try again)"
    rm -rf "$dir"
  done
}

# install_missing demo|test: installs what the build needs (and, for test, what configuring
# the test targets needs) now; for test, starts the install of what only running the tests
# needs in the background (its pid in RUN_PACKAGES_PID, its output in build/run-packages.log).
RUN_PACKAGES_PID=
install_missing() {
  local wanted=("${BUILD_PACKAGES[@]}") later=()
  if [ "${1:-}" = test ]; then
    wanted+=("${TEST_PACKAGES[@]}")
    mapfile -t later < <(missing_of "${TEST_RUN_PACKAGES[@]}")
    # Node.js runs the independent MCAP validator and the viewer's clients; any installed
    # node/npm will do. A real browser loads the viewer page in the viewer tests.
    command -v node >/dev/null || later+=(nodejs)
    command -v npm >/dev/null || later+=(npm)
    command -v chromium >/dev/null || later+=(chromium)
  fi
  local missing
  mapfile -t missing < <(missing_of "${wanted[@]}")
  if [ ${#missing[@]} -gt 0 ] || [ ${#later[@]} -gt 0 ]; then
    as_root apt-get update -q
  fi
  if [ ${#missing[@]} -gt 0 ]; then
    echo "run.sh: installing ${missing[*]}"
    apt_install "${missing[@]}"
  fi
  # Without root, sudo may have to ask for a password: then nothing runs in the background.
  if [ ${#later[@]} -gt 0 ] && [ "$(id -u)" -ne 0 ] && ! sudo -n true 2>/dev/null; then
    echo "run.sh: installing ${later[*]}"
    apt_install "${later[@]}"
    later=()
  fi
  if [ "${1:-}" = test ]; then
    mkdir -p build
    echo "run.sh: installing ${later[*]:-nothing} and filling the npm cache in the background (build/run-packages.log)"
    (
      set -e
      [ ${#later[@]} -eq 0 ] || apt_install "${later[@]}"
      npm_cache_warm
    ) >build/run-packages.log 2>&1 </dev/null &
    RUN_PACKAGES_PID=$!
  fi
}

# Waits for the background install; fails with its log when it failed.
wait_run_packages() {
  [ -n "$RUN_PACKAGES_PID" ] || return 0
  if ! wait "$RUN_PACKAGES_PID"; then
    tail -n 30 build/run-packages.log >&2
    echo "run.sh: installing the packages the tests need failed (build/run-packages.log)" >&2
    exit 1
  fi
}

# build TARGET: configure and build TARGET (all, or demo_programs for the demo alone).
build() {
  local werror=OFF launcher=() generator=()
  [ "${CI:-}" = true ] && werror=ON
  # ccache, where the machine has it, makes rebuilds after a fresh clone cheap (not required).
  command -v ccache >/dev/null &&
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  # Ninja keeps both cores compiling (a target's file need not wait for the libraries it links);
  # a build/ configured earlier keeps its generator.
  [ -f build/CMakeCache.txt ] || generator=(-G Ninja)
  cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DSB_WERROR="$werror" \
    -DSB_ONLY= "${launcher[@]}" >/dev/null
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
    distributed_test | rogue_host_test | frame_transport_test) no_namespaces ;;
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
    wait_run_packages
    cd build
    shift
    status=0
    # One test more than cores: most tests spend much of their time waiting on DDS and
    # child processes, so a third test on two cores shortens the run without starving them.
    ctest --output-on-failure -j"$(($(nproc) + 1))" --timeout 900 --output-junit Testing/junit.xml "$@" ||
      status=$?
    check_skips Testing/junit.xml || status=1
    exit "$status"
    ;;
  build)
    install_missing test
    build all
    wait_run_packages
    ;;
  *)
    echo "usage: bash run.sh demo|test|build" >&2
    exit 2
    ;;
esac
