#!/usr/bin/env bash
# Builds ale-slam for the host or for armhf (Debian's cross compiler, fully static).
#
#   scripts/build.sh host|armhf|host-asan|host-fuzz [Debug|Release] [NINJA_TARGET...]
#                                    binaries end up in build/<target>/bin/; with ninja targets
#                                    (e.g. ale-slamd ale-eval) only those and what they need
#
# host-asan is the host build with AddressSanitizer, LeakSanitizer and UndefinedBehaviorSanitizer
# (toolchains/host-asan.cmake), benchmarks off; scripts/test.sh runs the host tests on it too.
# host-fuzz is Clang's libFuzzer with AddressSanitizer and UndefinedBehaviorSanitizer
# (toolchains/host-fuzz.cmake): without ninja targets it builds only the fuzz targets (tests/fuzz/,
# ninja target ale_fuzzers) and the libraries they link; its tests are short fuzzing runs
# (docs/fuzzing.md).
#
# Dependencies are located (and built once, if missing) by scripts/setup-deps.sh.
# ALE_JOBS sets the build parallelism (default: number of cores). ALE_KEEP_GOING=1 builds every
# target that does not depend on a failed one (ninja -k 0) and still exits non-zero on a failure.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
target=${1:-}
type=${2:-Release}
shift $(( $# < 2 ? $# : 2 ))
only=()
[ $# -eq 0 ] || only=(--target "$@")
deps=$target
extra=()
case "$target" in
  host) toolchain=$root/toolchains/host.cmake ;;
  armhf) toolchain=$root/toolchains/armhf-linux-gnueabihf.cmake ;;
  host-asan) toolchain=$root/toolchains/host-asan.cmake deps=host extra=(-DALE_BUILD_BENCHMARKS=OFF) ;;
  host-fuzz) toolchain=$root/toolchains/host-fuzz.cmake deps=host extra=(-DALE_BUILD_TESTS=OFF -DALE_BUILD_BENCHMARKS=OFF)
             [ ${#only[@]} -gt 0 ] || only=(--target ale_fuzzers) ;;
  *) echo "usage: scripts/build.sh host|armhf|host-asan|host-fuzz [Debug|Release] [NINJA_TARGET...]" >&2; exit 2 ;;
esac
case "$type" in Debug|Release|RelWithDebInfo) ;; *) echo "build type must be Debug or Release" >&2; exit 2 ;; esac

prefix=$("$root/scripts/setup-deps.sh" "$deps" | sed -n "s/^ALE_DEPS_$deps=//p")
[ -n "$prefix" ] || { echo "build.sh: setup-deps.sh gave no dependency prefix for $deps" >&2; exit 1; }

build=$root/build/$target
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_TOOLCHAIN_FILE="$toolchain" \
  -DCMAKE_BUILD_TYPE="$type" -DALE_DEPS_PREFIX="$prefix" -DOpenCV_DIR="$prefix/lib/cmake/opencv4" "${extra[@]}" >/dev/null
keep_going=()
[ "${ALE_KEEP_GOING:-0}" = 1 ] && keep_going=(-- -k 0)
cmake --build "$build" -j "${ALE_JOBS:-$(nproc)}" "${only[@]}" "${keep_going[@]}"
echo "build.sh: $target $type binaries${only:+ (${only[*]:1})} in build/$target/bin"
