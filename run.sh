#!/usr/bin/env bash
# One entry point for a fresh Debian bookworm machine (run as root, or with sudo available):
#   bash run.sh demo [demo args...]   install what is missing, build, run the whole system
#                                     on the built-in simulator (stereoball demo)
#   bash run.sh test                  install what is missing, build, run the test suite (ctest)
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
# for the interop test, dpkg-dev + file for the package test.
TEST_PACKAGES=(
  iproute2
  fastddsgen libfastrtps-dev libfastcdr-dev dpkg-dev file
  clang libclang-rt-14-dev
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
    exec ctest --output-on-failure -j"$(nproc)" --timeout 900
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
