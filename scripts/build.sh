#!/usr/bin/env bash
# Builds ale-slam for the host or for armhf (Debian's cross compiler, fully static).
#
#   scripts/build.sh host|armhf [Debug|Release]     binaries end up in build/<target>/bin/
#
# Dependencies are located (and built once, if missing) by scripts/setup-deps.sh.
# ALE_JOBS sets the build parallelism (default: number of cores).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
target=${1:-}
type=${2:-Release}
case "$target" in
  host) toolchain=$root/toolchains/host.cmake ;;
  armhf) toolchain=$root/toolchains/armhf-linux-gnueabihf.cmake ;;
  *) echo "usage: scripts/build.sh host|armhf [Debug|Release]" >&2; exit 2 ;;
esac
case "$type" in Debug|Release|RelWithDebInfo) ;; *) echo "build type must be Debug or Release" >&2; exit 2 ;; esac

prefix=$("$root/scripts/setup-deps.sh" "$target" | sed -n "s/^ALE_DEPS_$target=//p")
[ -n "$prefix" ] || { echo "build.sh: setup-deps.sh gave no dependency prefix for $target" >&2; exit 1; }

build=$root/build/$target
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_TOOLCHAIN_FILE="$toolchain" \
  -DCMAKE_BUILD_TYPE="$type" -DALE_DEPS_PREFIX="$prefix" -DOpenCV_DIR="$prefix/lib/cmake/opencv4" >/dev/null
cmake --build "$build" -j "${ALE_JOBS:-$(nproc)}"
echo "build.sh: $target $type binaries in build/$target/bin"
