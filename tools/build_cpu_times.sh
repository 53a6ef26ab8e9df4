#!/usr/bin/env bash
# CPU time of a build, per compile and link, independent of how busy the machine is.
#   tools/build_cpu_times.sh BUILD_DIR [cmake configure args...] [-- build args...]
# Configures BUILD_DIR from scratch (no ccache: every file is compiled), builds it under
# `nice -n 19` with every compiler and linker call timed, and prints the total user+sys CPU
# time, the slowest calls and an estimate of the wall clock on two idle cores.
# As a launcher alone: SB_CPU_LOG=FILE tools/build_cpu_times.sh --launch COMMAND...
set -euo pipefail
if [ "${1:-}" = --launch ]; then
  shift
  out=?
  prev=
  for arg in "$@"; do
    [ "$prev" = -o ] && out=$arg
    prev=$arg
  done
  exec /usr/bin/time -a -o "${SB_CPU_LOG:?}" -f "%U %S %e $out" "$@"
fi
here=$(dirname "$(readlink -f "$0")")
src=$(dirname "$here")
dir=${1:?usage: build_cpu_times.sh BUILD_DIR [configure args] [-- build args]}
shift
configure=()
while [ $# -gt 0 ] && [ "$1" != -- ]; do
  configure+=("$1")
  shift
done
[ "${1:-}" = -- ] && shift
# Only a build folder (or nothing) is replaced.
if [ -e "$dir" ] && [ ! -f "$dir/CMakeCache.txt" ] && [ -n "$(ls -A "$dir")" ]; then
  echo "build_cpu_times.sh: $dir is not an empty or CMake build folder; not replacing it" >&2
  exit 2
fi
rm -rf "$dir"
mkdir -p "$dir"
dir=$(readlink -f "$dir")
log=$dir/cpu_times.log
: >"$log"
export SB_CPU_LOG=$log CCACHE_DISABLE=1
launcher=$here/build_cpu_times.sh
cmake -S "$src" -B "$dir" -DCMAKE_BUILD_TYPE=Release -DSB_ONLY= \
  "-DCMAKE_CXX_COMPILER_LAUNCHER=$launcher;--launch" "-DCMAKE_C_COMPILER_LAUNCHER=$launcher;--launch" \
  "-DCMAKE_CXX_LINKER_LAUNCHER=$launcher;--launch" "${configure[@]}" >/dev/null
/usr/bin/time -o "$dir/cpu_total.txt" -f "%U %S %e" nice -n 19 cmake --build "$dir" -j2 "$@" >"$dir/build.log" 2>&1
read -r user sys wall <"$dir/cpu_total.txt"
awk -v user="$user" -v sys="$sys" -v wall="$wall" '
  { cpu = $1 + $2; n++; sum += cpu; if ($4 ~ /\.o$/) { nc++; csum += cpu } else { nl++; lsum += cpu } }
  END {
    printf "whole build: user %.0f s + sys %.0f s = %.0f s CPU (wall %.0f s on a shared machine)\n", user, sys, user + sys, wall
    printf "compiles: %d calls, %.0f s CPU; links and others: %d calls, %.0f s CPU\n", nc, csum, nl, lsum
    printf "two idle cores: about %.0f s (whole CPU / 2)\n", (user + sys) / 2
  }' "$log"
echo "slowest calls (user+sys s, output):"
awk '{ printf "%7.1f %s\n", $1 + $2, $4 }' "$log" | sort -rn | head -"${SB_CPU_TOP:-15}"
