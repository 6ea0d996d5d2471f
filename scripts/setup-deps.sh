#!/usr/bin/env bash
# Installs what the host and armhf builds need, from Debian's archive only, and builds the
# pieces Debian does not ship as static armhf archives (OpenCV core+imgproc with NEON, LCM's
# C library) from Debian's own source tarballs into a cache keyed by version.
# Idempotent: a second run with everything present takes seconds.
#
#   scripts/setup-deps.sh [all]      install packages (if missing) and build the cached deps
#   scripts/setup-deps.sh host|armhf only what that build needs (host: no armhf packages)
#   scripts/setup-deps.sh packages   only the Debian packages of all (builds nothing)
#   scripts/setup-deps.sh icount     only qemu-arm with TCG plugins, for scripts/arm-icount.sh (a
#                                    measurement tool: neither the build nor the tests need it)
#   ALE_DEPS_CACHE=DIR               where built dependencies are cached
#                                    (default: ${XDG_CACHE_HOME:-$HOME/.cache}/ale-slam)
#   ALE_APT_LOCK_WAIT=SECONDS        how long to wait for another apt/dpkg holding the lock (600)
# Resolves the version skew apt will not (Multi-Arch: same packages whose native and armhf
# versions differ, packages installed at versions the archive lacks: skew_prefs), waits for
# another apt holding the lock (ALE_APT_LOCK_WAIT) and says in one line what it changed on the
# machine.
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

# What the host build and its tests need (tests/host: GoogleTest, Ceres as the bundle adjuster's
# reference, a JDK and LCM's Java library for the Java decoder test and scripts/lcm-spy.sh), and
# the fuzz build (host-fuzz, tests/fuzz: Clang 14 and its runtime with libFuzzer, which apt does
# not install with clang-14 without recommends).
host_pkgs=(build-essential cmake ninja-build pkg-config curl xz-utils file ca-certificates python3
  googletest libgtest-dev libbenchmark-dev
  libeigen3-dev libgpiod-dev liblcm-bin libglib2.0-dev libpcre2-dev
  libpng-dev zlib1g-dev libjpeg62-turbo-dev
  libceres-dev openjdk-17-jdk-headless liblcm-java libjchart2d-java
  clang-14 libclang-rt-14-dev)
# What the armhf build adds: the cross compiler, qemu-arm for its tests, armhf static archives.
armhf_pkgs=(crossbuild-essential-armhf qemu-user-static
  libgpiod-dev:armhf libglib2.0-dev:armhf libpcre2-dev:armhf libpng-dev:armhf
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

# How long to wait for another apt or dpkg (unattended upgrades on a machine that has just
# booted) before giving up, in seconds.
lock_wait=${ALE_APT_LOCK_WAIT:-600}
apt_locks=(/var/lib/dpkg/lock-frontend /var/lib/dpkg/lock /var/lib/apt/lists/lock /var/cache/apt/archives/lock)

# The process holding one of apt's or dpkg's locks ("PID (name)"), from /proc/locks; empty if none.
apt_lock_holder() {
  local f key pid
  for f in "${apt_locks[@]}"; do
    [ -e "$f" ] || continue
    key=$(stat -c '%Hd %Ld %i' "$f" | awk '{printf "%02x:%02x:%s", $1, $2, $3}')
    pid=$(awk -v k="$key" '$0 ~ /->/ {next} { for (i = 1; i <= NF; i++) if ($i == k) { print $(i - 1); exit } }' /proc/locks)
    [ -n "$pid" ] || continue
    # the holder may be this very script's apt-get of a moment ago, already gone
    [ -d "/proc/$pid" ] || continue
    echo "$pid ($(cat "/proc/$pid/comm" 2>/dev/null || echo '?'))"
    return
  done
}

# Waits (at most $lock_wait s) until no other process holds apt's or dpkg's locks.
wait_apt_locks() {
  local holder waited=0
  holder=$(apt_lock_holder)
  [ -n "$holder" ] || return 0
  log "another package manager holds the dpkg/apt lock (process $holder); waiting up to ${lock_wait}s for it to finish"
  while [ -n "$holder" ]; do
    [ "$waited" -lt "$lock_wait" ] ||
      die "the dpkg/apt lock is still held by process $holder after ${lock_wait}s; let it finish (or stop it) and run again (ALE_APT_LOCK_WAIT=SECONDS waits longer)"
    sleep 5; waited=$((waited + 5))
    holder=$(apt_lock_holder)
  done
  log "the lock is free after ${waited}s"
}

# apt-get that waits for the locks (ours first, with a message; apt's own timeout covers a race).
apt_get() {
  wait_apt_locks
  sudo_ env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout="$lock_wait" "$@"
}

# closure PKGS...: the packages apt would install for them (approximately: first alternatives,
# native providers preferred), natives without suffix, foreign ones with ":arch"
closure() {
  local native; native=$(dpkg --print-architecture)
  local seen frontier next
  seen=$(printf '%s\n' "$@" | sed "s/:$native\$//" | LC_ALL=C sort -u)
  frontier=$seen
  while [ -n "$frontier" ]; do
    next=$(apt-cache depends --no-recommends --no-suggests --no-conflicts --no-breaks --no-replaces \
             --no-enhances $frontier 2>/dev/null | awk -v n="$native" '
      function flush(   i, k, c, pick) {
        if (!have) return
        k = split(cands, c, " ")
        pick = ""
        for (i = 1; i <= k; i++) if (c[i] !~ /:/ || c[i] ~ (":" n "$")) { pick = c[i]; break }
        if (pick == "" && k > 0) pick = c[1]
        sub(":" n "$", "", pick)
        if (pick != "" && take) print pick
        have = 0
      }
      /^[^ ]/ { flush(); prev_alt = 0; next }
      /^  [|]?[A-Za-z]*Depends: / {
        flush()
        alt = ($1 ~ /^\|/)
        take = !prev_alt; prev_alt = alt
        name = $2; virtual = (name ~ /^</); gsub(/[<>]/, "", name)
        cands = virtual ? "" : name; have = 1
        next
      }
      /^    / { if (have) cands = cands " " $1; next }
      END { flush() }' | LC_ALL=C sort -u)
    frontier=$(LC_ALL=C comm -13 <(printf '%s\n' "$seen") <(printf '%s\n' "$next"))
    seen=$(printf '%s\n%s\n' "$seen" "$frontier" | LC_ALL=C sort -u | sed '/^$/d')
  done
  printf '%s\n' "$seen"
}

# Version skew apt will not resolve by itself, as it does not downgrade unasked. A machine's image
# may hold native builds newer than the archive serves (made from a newer snapshot, or from a
# bookworm-security index that verifies for the native architecture and not for armhf):
# - Multi-Arch: same packages must have one version on every architecture: for each one in the
#   dependency closure of what is to be installed (closure()) with an armhf twin there, whose
#   native installed version or native candidate differs from the armhf candidate, the armhf
#   candidate becomes the candidate of both;
# - any other package of the closure installed at a version the archive does not have (a -dev
#   package asks for its library's exact version) gets the version the archive serves with the
#   highest priority (the highest of those on a tie), which apt's candidate is not when the
#   installed one is higher.
# Prints apt preferences stanzas for those (priority 1001: a downgrade if need be; apt applies
# them only to the packages its resolution touches), each after a line "# P:ARCH OLD -> NEW".
skew_prefs() { # packages...
  local native; native=$(dpkg --print-architecture)
  local closure
  closure=$(closure "$@")
  [ -n "$closure" ] || return 0
  local bases natives same=
  bases=$(printf '%s\n' "$closure" | sed -n 's/:armhf$//p')
  natives=$(printf '%s\n' "$closure" | grep -v ':armhf$' | sed "s/:$native\$//")
  # the Multi-Arch field of each armhf candidate
  if [ -n "$bases" ]; then
    same=$(apt-cache show --no-all-versions $(printf '%s:armhf\n' $bases) 2>/dev/null |
             awk '/^Package:/{p = $2} /^Multi-Arch: same/{print p}' | LC_ALL=C sort -u)
  fi
  # installed and candidate versions, and whether the archive has the installed one (apt-cache
  # policy names the native packages without ":arch")
  apt-cache policy $natives $(for b in $same; do echo "$b:armhf" "$b:$native"; done) 2>/dev/null |
    awk -v n="$native" -v same="$same" '
      /^[^ ].*:$/ {p = substr($0, 1, length($0) - 1); if (p !~ /:/) p = p ":" n; names[p] = 1; next}
      /^  Installed:/ {inst[p] = $2; next}
      /^  Candidate:/ {cand[p] = $2; next}
      /^ \*\*\* / {v = $2; prio = $3; next}
      /^     [^ ]/ {v = $1; prio = $2; next}
      /^        [0-9-]/ {
        if ($2 == "/var/lib/dpkg/status" || (p, v) in served) next
        served[p, v] = 1
        # the table lists versions from the highest down: the first at the top priority wins
        if (!(p in best) || prio + 0 > best_prio[p]) {best[p] = v; best_prio[p] = prio + 0}
      }
      function pin(what, old, new, names) {
        printf "# %s %s -> %s\nPackage: %s\nPin: version %s\nPin-Priority: 1001\n\n", what, old, new, names, new
        }
      function known(v) { return v != "" && v != "(none)" }
      END {
        k = split(same, ms, "\n")
        for (i = 1; i <= k; i++) {
          b = ms[i]; if (b == "") continue
          q = b ":" n; ca = cand[b ":armhf"]; have = inst[q]
          if (!known(have)) have = cand[q]
          done[q] = 1
          # the installed version, or the candidate apt would upgrade to, differs
          if (known(ca) && ((known(inst[q]) && inst[q] != ca) || (known(cand[q]) && cand[q] != ca)))
            pin(q, have, ca, b " " b ":armhf")
        }
        for (q in names) {
          if (q in done || q ~ /:armhf$/) continue
          if (known(inst[q]) && (q in best) && !((q, inst[q]) in served))
            pin(q, inst[q], best[q], substr(q, 1, length(q) - length(n) - 1))
        }
      }'
}

# "name version" of every installed package, for the one line saying what changed.
installed_list() { LC_ALL=C dpkg-query -W -f='${db:Status-Abbrev} ${binary:Package} ${Version}\n' | awk '$1 == "ii" {print $2, $3}' | LC_ALL=C sort; }

install_pkgs() { # packages...
  local missing
  missing=$(missing_pkgs "$@")
  if [ -z "$missing" ]; then log "all packages present: nothing changed on this machine"; return; fi
  log "installing:" $missing
  local changes=() before after
  before=$(installed_list)
  if printf '%s\n' $missing | grep -q ':armhf$' && ! dpkg --print-foreign-architectures | grep -qx armhf; then
    sudo_ dpkg --add-architecture armhf
    changes+=("added the armhf architecture")
  fi
  # A failed index (some mirrors serve a bookworm-security armhf index that fails to verify) is
  # not fatal: apt goes on with the others, and the skew it leaves is resolved below.
  local upd
  wait_apt_locks  # here, not inside the capture below, so that its message shows
  if ! upd=$(apt_get update -q 2>&1); then
    log "apt-get update reported errors (apt goes on without those indexes):"
    printf '%s\n' "$upd" | grep -E '^(E|W):' | sed 's/^/  /' >&2
  fi
  # the machine's own preferences, then ours for the skew
  local prefs; prefs=$(mktemp)
  cat /etc/apt/preferences >"$prefs" 2>/dev/null || true
  local skew
  skew=$(skew_prefs $missing)
  printf '%s\n' "$skew" >>"$prefs"
  [ -z "$skew" ] || log "version skew apt will not resolve by itself (the archive's version taken where apt needs it, armhf's for Multi-Arch: same):" \
    $(printf '%s\n' "$skew" | sed -n 's/^# \([^ ]*\) .*/\1/p')
  chmod 644 "$prefs"
  apt_get -o Dir::Etc::Preferences="$prefs" install -y -q --no-install-recommends --allow-downgrades $missing ||
    { rm -f "$prefs"; die "apt-get could not install the packages (its messages above)"; }
  rm -f "$prefs"
  after=$(installed_list)
  # what changed: packages new on the machine, and versions changed
  local new changed
  new=$(LC_ALL=C join -v 2 <(printf '%s\n' "$before" | awk '{print $1}') <(printf '%s\n' "$after" | awk '{print $1}') | wc -l)
  changed=$(LC_ALL=C join <(printf '%s\n' "$before") <(printf '%s\n' "$after") |
              awk '$2 != $3 {printf "%s%s %s -> %s", sep, $1, $2, $3; sep = ", "}')
  changes+=("installed $new packages ($(printf '%s\n' $missing | wc -l) asked for, the rest their dependencies)")
  [ -z "$changed" ] || changes+=("changed versions: $changed")
  log "changed on this machine: $(printf '%s; ' "${changes[@]}" | sed 's/; $//')"
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
  log "building OpenCV $OPENCV_VERSION ($modules) for $arch (a few minutes)"
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
  case "$which" in
    all|armhf|packages) install_pkgs "${host_pkgs[@]}" "${armhf_pkgs[@]}" ;;
    host) install_pkgs "${host_pkgs[@]}" ;;
    *) die "unknown part '$which' (all, host, armhf, packages or icount)" ;;
  esac
  [ "$which" != packages ] || return 0
  for a in host armhf; do
    [ "$which" = all ] || [ "$which" = "$a" ] || continue
    p=$(build_arch $a)
    echo "ALE_DEPS_$a=$p"
  done
}
# sourced (tests/host/scripts/setup_deps_test.sh): the functions only. The exit on the same line
# keeps bash from reading on in this file after main, which an edit during a run would derail.
[ "${BASH_SOURCE[0]}" != "$0" ] || { main "$@"; exit; }
