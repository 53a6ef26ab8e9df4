#!/usr/bin/env bash
# One entry point for a fresh Debian bookworm machine (run as root, or with sudo available):
#   bash run.sh demo [demo args...]   install what is missing, build, run the whole system
#                                     on the built-in simulator (stereoball demo)
#   bash run.sh test                  install what is missing, build, run the test suite (ctest)
#   bash run.sh build                 install what is missing and build only
# Builds go to build/, programs to build/bin/.
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")"

PACKAGES=(
  build-essential cmake pkg-config git
  cyclonedds-dev cyclonedds-tools
  libopencv-dev libeigen3-dev libyaml-cpp-dev libcli11-dev libzstd-dev libv4l-dev
  nlohmann-json3-dev zlib1g-dev libjpeg-dev libgtest-dev libgmock-dev
  iproute2
  clang libclang-rt-14-dev
)

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else
    echo "run.sh: need root (or sudo) to install: $*" >&2; exit 1
  fi
}

install_missing() {
  local missing=()
  for pkg in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
  done
  # Node.js runs the independent MCAP validator in the tests; any installed node/npm will do.
  if [ "${1:-}" = test ]; then
    command -v node >/dev/null || missing+=(nodejs)
    command -v npm >/dev/null || missing+=(npm)
  fi
  if [ ${#missing[@]} -gt 0 ]; then
    echo "run.sh: installing ${missing[*]}"
    as_root apt-get update -q
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
  fi
}

build() {
  local werror=OFF
  [ "${CI:-}" = true ] && werror=ON
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DSB_WERROR="$werror" -DSB_ONLY= >/dev/null
  cmake --build build -j"$(nproc)"
}

case "${1:-}" in
  demo)
    install_missing demo
    build
    shift
    exec build/bin/stereoball demo "$@"
    ;;
  test)
    install_missing test
    build
    cd build
    exec ctest --output-on-failure -j"$(nproc)" --timeout 900
    ;;
  build)
    install_missing build
    build
    ;;
  *)
    echo "usage: bash run.sh demo|test|build" >&2
    exit 2
    ;;
esac
