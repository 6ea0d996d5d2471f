#!/usr/bin/env bash
# Installs what the host and armhf builds need, from Debian's archive only, and builds the
# pieces Debian does not ship as static armhf archives (OpenCV core+imgproc with NEON, LCM's
# C library) from Debian's own source tarballs into a cache keyed by version.
# Idempotent: a second run with everything present takes seconds.
#
#   scripts/setup-deps.sh            install packages (if missing) and build the cached deps
#   scripts/setup-deps.sh icount     only qemu-arm with TCG plugins, for scripts/arm-icount.sh (a
#                                    measurement tool: neither the build nor the tests need it)
#   ALE_DEPS_CACHE=DIR               where built dependencies are cached
#                                    (default: ${XDG_CACHE_HOME:-$HOME/.cache}/ale-slam)
# Prints the prefix of each architecture's dependencies on its last lines.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cache=${ALE_DEPS_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/ale-slam}
log() { printf 'setup-deps: %s\n' "$*" >&2; }
die() { printf 'setup-deps: error: %s\n' "$*" >&2; exit 1; }

OPENCV_VERSION=4.6.0
OPENCV_TARBALL=opencv_4.6.0+dfsg.orig.tar.xz
OPENCV_SHA256=40a59ba7e5c18a43652de0a08733c9843a39bba619b1f3e26a5fac4a6f041423
LCM_VERSION=1.3.1
LCM_TARBALL=lcm_1.3.1+repack1.orig.tar.gz
LCM_SHA256=abf293e54aff3d073cb4f9d4d5a261eab0e5ffea02e13fd601715c11612b85e8
BENCHMARK_VERSION=1.7.1
BENCHMARK_TARBALL=benchmark_1.7.1.orig.tar.gz
BENCHMARK_SHA256=6430e4092653380d9dc4ccb45a1e2dc9259d581f4866dc0759713126056bc1d7
# qemu-arm with plugins (scripts/arm-icount.sh): the source of bookworm's qemu-user-static, so
# its translator splits blocks as the qemu-arm-static that ../shared/tools/arm_icount.py runs.
QEMU_VERSION=7.2+dfsg-7+deb12u18
QEMU_TARBALL=qemu_7.2+dfsg.orig.tar.xz
QEMU_SHA256=91aca71520040edc40b8d437aa3004dae614f58e286cf653ee8996c07af2962f
QEMU_DEBIAN_TARBALL=qemu_$QEMU_VERSION.debian.tar.xz
QEMU_DEBIAN_SHA256=28a1c86310ee53b6bf1854cffe6f6be6ed29a08db7d05759f8ac57b8d6a6cb2f
# bump when the way an architecture's dependencies are configured changes, so caches are rebuilt
RECIPE_REV_host=3   # 2: features2d added (cv::ORB is the host benchmarks' reference); 3: calib3d (geometry tests' reference)
RECIPE_REV_armhf=1
RECIPE_REV_icount=1

host_pkgs=(build-essential cmake ninja-build pkg-config curl xz-utils file ca-certificates
  crossbuild-essential-armhf qemu-user-static
  googletest libgtest-dev libbenchmark-dev
  libeigen3-dev libgpiod-dev liblcm-bin libglib2.0-dev libpcre2-dev
  libpng-dev zlib1g-dev libjpeg62-turbo-dev
  libceres-dev   # Ceres: host-only reference solver of the bundle-adjustment tests and benchmarks
  openjdk-17-jdk-headless liblcm-java libjchart2d-java)  # scripts/lcm-spy.sh; the Java decoder of the LCM log test
armhf_pkgs=(libgpiod-dev:armhf libglib2.0-dev:armhf libpcre2-dev:armhf libpng-dev:armhf
  zlib1g-dev:armhf libjpeg62-turbo-dev:armhf)

# only for `setup-deps.sh icount`: what qemu's build needs
icount_pkgs=(build-essential ninja-build meson pkg-config libglib2.0-dev curl xz-utils ca-certificates patch)

sudo_() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }

missing_pkgs() {
  local p
  for p in "$@"; do
    dpkg-query -W -f='${Status}\n' "$p" 2>/dev/null | grep -q '^install ok installed' || echo "$p"
  done
}

install_pkgs() { # packages...
  local missing
  missing=$(missing_pkgs "$@")
  if [ -z "$missing" ]; then log "all packages present"; return; fi
  log "installing:" $missing
  dpkg --print-foreign-architectures | grep -qx armhf || sudo_ dpkg --add-architecture armhf
  export DEBIAN_FRONTEND=noninteractive
  # The plain way first. Some mirrors serve a bookworm-security armhf index that fails to
  # verify; then armhf sees only bookworm and bookworm-updates, and packages that must have the
  # same version on both architectures must come from there too (see docs/building.md).
  if sudo_ apt-get update -q >/dev/null 2>&1 &&
     sudo_ apt-get install -y -q --no-install-recommends $missing; then
    return
  fi
  log "plain install failed; retrying from bookworm and bookworm-updates only"
  local parts; parts=$(mktemp -d)
  local uri
  uri=$(debian_mirror) || exit 1
  cat > "$parts/base.sources" <<SRC
Types: deb
URIs: $uri
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SRC
  local opts=(-o "Dir::Etc::SourceParts=$parts" -o "Dir::Etc::SourceList=/dev/null")
  sudo_ apt-get "${opts[@]}" update -q >/dev/null
  # Multi-Arch: same packages must have one version on both architectures: take the one
  # armhf can see (amd64 may already have a newer one from bookworm-security) for both.
  local pins=() v
  for p in linux-libc-dev libc6-dev libc6; do
    v=$(apt-cache "${opts[@]}" policy "$p:armhf" | awk '/Candidate:/{print $2}')
    [ -n "$v" ] && [ "$v" != "(none)" ] && pins+=("$p=$v" "$p:armhf=$v")
  done
  sudo_ apt-get "${opts[@]}" install -y -q --no-install-recommends --allow-downgrades \
    "${pins[@]}" $missing
  rm -rf "$parts"
  sudo_ apt-get update -q >/dev/null 2>&1 || true
}

# The Debian archive this machine's apt uses (deb822 sources or the classic sources.list); there
# is no fallback address: a machine without one cannot reach an archive we know of.
debian_mirror() {
  local m
  m=$(awk '/^URIs:/{print $2; exit}' /etc/apt/sources.list.d/debian.sources /etc/apt/sources.list.d/*.sources \
        2>/dev/null || true)
  [ -n "$m" ] || m=$(awk '/^deb /{for (i = 2; i <= NF; i++) if ($i !~ /^\[/) {print $i; exit}}' \
                       /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null | head -n 1)
  [ -n "$m" ] || die "no Debian archive address in /etc/apt/sources.list or /etc/apt/sources.list.d/: add this machine's mirror to apt's sources"
  echo "$m"
}

fetch() { # tarball sha256 pool-subdir
  local f=$1 sum=$2 sub=$3 dl=$cache/downloads
  mkdir -p "$dl"
  if [ ! -f "$dl/$f" ] || ! echo "$sum  $dl/$f" | sha256sum -c --quiet - 2>/dev/null; then
    local mirror
    mirror=$(debian_mirror) || exit 1
    log "downloading $f from $mirror"
    curl -fsSL -o "$dl/$f.part" "${mirror%/}/pool/main/$sub/$f" || die "cannot download $f from Debian's pool"
    echo "$sum  $dl/$f.part" | sha256sum -c --quiet - || die "checksum mismatch for $f"
    mv "$dl/$f.part" "$dl/$f"
  fi
  echo "$dl/$f"
}

# Google Benchmark for armhf: Debian ships no static armhf archive of it.
build_benchmark() { # prefix toolchain-args...
  local prefix=$1; shift
  local stamp=$prefix/.complete-benchmark-$BENCHMARK_VERSION
  [ -f "$stamp" ] && return
  local work=$cache/work/benchmark-$$; rm -rf "$work"; mkdir -p "$work"
  local tb; tb=$(fetch $BENCHMARK_TARBALL $BENCHMARK_SHA256 b/benchmark)
  tar -C "$work" -xzf "$tb"
  log "building Google Benchmark $BENCHMARK_VERSION"
  cmake -G Ninja -S "$work/benchmark-$BENCHMARK_VERSION" -B "$work/build" "$@" -DCMAKE_BUILD_TYPE=Release \
    -DBENCHMARK_ENABLE_TESTING=OFF -DBENCHMARK_ENABLE_GTEST_TESTS=OFF -DBENCHMARK_ENABLE_WERROR=OFF \
    -DBENCHMARK_ENABLE_INSTALL=ON -DBUILD_SHARED_LIBS=OFF -DCMAKE_INSTALL_PREFIX="$prefix" >"$work/log" 2>&1 ||
    die "Google Benchmark configure failed (see $work/log)"
  cmake --build "$work/build" >>"$work/log" 2>&1 && cmake --install "$work/build" >>"$work/log" 2>&1 ||
    die "Google Benchmark build failed (see $work/log)"
  touch "$stamp"
  rm -rf "$work"
}

build_arch() { # host|armhf
  local arch=$1 cc
  if [ "$arch" = armhf ]; then cc=arm-linux-gnueabihf-gcc; else cc=gcc; fi
  local ccver; ccver=$($cc -dumpfullversion)
  local rev_var=RECIPE_REV_$arch
  local key="opencv-$OPENCV_VERSION-lcm-$LCM_VERSION-gcc-$ccver-r${!rev_var}"
  local prefix=$cache/$arch/$key
  if [ -f "$prefix/.complete" ]; then
    [ "$arch" = armhf ] && build_benchmark "$prefix" -DCMAKE_TOOLCHAIN_FILE="$here/toolchains/armhf-linux-gnueabihf.cmake"
    log "$arch deps cached in $prefix"; echo "$prefix"; return
  fi
  local work=$cache/work/$arch; rm -rf "$work" "$prefix"; mkdir -p "$work"
  local ocv lcm; ocv=$(fetch $OPENCV_TARBALL $OPENCV_SHA256 o/opencv); lcm=$(fetch $LCM_TARBALL $LCM_SHA256 l/lcm)
  tar -C "$work" -xJf "$ocv"; tar -C "$work" -xzf "$lcm"
  local tc=() ocvarch=() zl modules=core,imgproc
  if [ "$arch" = armhf ]; then
    tc=(-DCMAKE_TOOLCHAIN_FILE="$here/toolchains/armhf-linux-gnueabihf.cmake")
    ocvarch=(-DENABLE_NEON=ON -DCPU_BASELINE=NEON -DCPU_DISPATCH= -DCPU_NEON_FLAGS_ON=-mfpu=neon-vfpv4)
    zl=/usr/lib/arm-linux-gnueabihf/libz.a
  else
    tc=(-DCMAKE_TOOLCHAIN_FILE="$here/toolchains/host.cmake")
    # features2d and calib3d only on the host: cv::ORB is the reference in the feature
    # benchmarks, calib3d in the geometry tests; the product links core and imgproc only.
    modules=core,imgproc,features2d,calib3d
    zl=/usr/lib/x86_64-linux-gnu/libz.a
  fi
  log "building LCM $LCM_VERSION for $arch"
  cmake -G Ninja -S "$here/cmake/deps/lcm" -B "$work/build-lcm" "${tc[@]}" -DCMAKE_BUILD_TYPE=Release \
    -DLCM_SOURCE_DIR="$work/lcm-$LCM_VERSION" -DCMAKE_INSTALL_PREFIX="$prefix" >"$work/lcm.log"
  cmake --build "$work/build-lcm" >>"$work/lcm.log" && cmake --install "$work/build-lcm" >>"$work/lcm.log"
  log "building OpenCV $OPENCV_VERSION core+imgproc for $arch (a few minutes)"
  cmake -G Ninja -S "$work/opencv-$OPENCV_VERSION" -B "$work/build-ocv" -C "$here/cmake/deps/opencv-options.cmake" \
    "${tc[@]}" -DCMAKE_BUILD_TYPE=Release -DBUILD_LIST=$modules "${ocvarch[@]}" -DZLIB_LIBRARY=$zl -DZLIB_INCLUDE_DIR=/usr/include \
    -DCMAKE_INSTALL_PREFIX="$prefix" >"$work/ocv.log"
  if [ "$arch" = armhf ]; then
    grep -q 'Baseline:.*NEON' "$work/ocv.log" || die "OpenCV for armhf configured without NEON (see $work/ocv.log)"
  fi
  cmake --build "$work/build-ocv" >>"$work/ocv.log" 2>&1 || die "OpenCV build failed (see $work/ocv.log)"
  cmake --install "$work/build-ocv" >>"$work/ocv.log"
  touch "$prefix/.complete"
  rm -rf "$work"
  [ "$arch" = armhf ] && build_benchmark "$prefix" "${tc[@]}"
  echo "$prefix"
}

# qemu-arm (linux-user only, TCG plugins on, a dynamic host binary) from Debian's qemu source:
# the orig tarball with the package's patches (the 7.2.x stable series among them) in the order of
# debian/patches/series.
build_qemu_icount() {
  local key="qemu-$QEMU_VERSION-gcc-$(gcc -dumpfullversion)-r$RECIPE_REV_icount"
  local prefix=$cache/icount/$key
  if [ -f "$prefix/.complete" ]; then log "qemu-arm with plugins cached in $prefix"; echo "$prefix"; return; fi
  local installed
  installed=$(dpkg-query -W -f='${Version}' qemu-user-static 2>/dev/null || true)
  installed=${installed#*:}  # without the epoch
  case "$installed" in "$QEMU_VERSION"*) ;; *)
    log "note: qemu-user-static here is '$installed', the counter builds $QEMU_VERSION" ;;
  esac
  local work=$cache/work/icount; rm -rf "$work" "$prefix"; mkdir -p "$work"
  local orig deb; orig=$(fetch $QEMU_TARBALL $QEMU_SHA256 q/qemu); deb=$(fetch "$QEMU_DEBIAN_TARBALL" $QEMU_DEBIAN_SHA256 q/qemu)
  tar -C "$work" -xJf "$orig"; tar -C "$work" -xJf "$deb"
  local src=$work/qemu-7.2.0 p
  [ -d "$src" ] || die "unexpected layout of $QEMU_TARBALL (no qemu-7.2.0/)"
  for p in $(grep -v '^#' "$work/debian/patches/series"); do
    patch -d "$src" -p1 -s <"$work/debian/patches/$p" >>"$work/patch.log" 2>&1 || die "patch $p does not apply (see $work/patch.log)"
  done
  log "building qemu-arm $QEMU_VERSION with plugins (a few minutes)"
  mkdir -p "$work/build"
  (cd "$work/build" && "$src/configure" --prefix="$prefix" --target-list=arm-linux-user --disable-system \
     --enable-linux-user --without-default-features --enable-plugins --disable-docs --disable-werror) \
     >"$work/configure.log" 2>&1 || die "qemu configure failed (see $work/configure.log)"
  ninja -C "$work/build" qemu-arm >"$work/build.log" 2>&1 || die "qemu build failed (see $work/build.log)"
  mkdir -p "$prefix/bin" "$prefix/include"
  install -m 755 "$work/build/qemu-arm" "$prefix/bin/qemu-arm"
  install -m 644 "$src/include/qemu/qemu-plugin.h" "$prefix/include/qemu-plugin.h"
  "$prefix/bin/qemu-arm" --version | grep -q 'version 7\.2' || die "the qemu-arm built does not run"
  touch "$prefix/.complete"
  rm -rf "$work"
  echo "$prefix"
}

main() {
  mkdir -p "$cache"
  local which=${1:-all} p
  # One setup at a time: concurrent builds (several shells, CI jobs) wait here. The counter's qemu
  # shares nothing with the other dependencies but apt (which has its own lock): a lock of its own.
  if [ "$which" = icount ]; then
    exec 9>"$cache/.lock-icount"
    flock 9
    install_pkgs "${icount_pkgs[@]}"
    p=$(build_qemu_icount)
    echo "ALE_DEPS_icount=$p"
    return
  fi
  exec 9>"$cache/.lock"
  flock 9
  install_pkgs "${host_pkgs[@]}" "${armhf_pkgs[@]}"
  for a in host armhf; do
    [ "$which" = all ] || [ "$which" = "$a" ] || continue
    p=$(build_arch $a)
    echo "ALE_DEPS_$a=$p"
  done
}
main "$@"
