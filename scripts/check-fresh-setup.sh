#!/usr/bin/env bash
# Proves the README's set-up on a fresh Debian 12 machine: builds a clean bookworm root with
# debootstrap from this machine's Debian mirror (bookworm, bookworm-updates, bookworm-security,
# as this machine's apt has them), gives it the Multi-Arch skew fresh cloud images have (a native
# build of a Multi-Arch: same library at a version the archive does not serve: libpcre2-8-0
# repacked as 10.42-1+deb12u9), holds dpkg's lock for a while as a just-booted machine's
# unattended upgrades would, copies the repository in (git archive of HEAD) and runs the README's
# two commands in it as a new user with sudo would. Run it before each release (not in CI: it
# takes long: docs/building.md). Needs root (or sudo) and about 6 GB in the work folder.
#
#   scripts/check-fresh-setup.sh [--demo-only|--root-only]
#
#   --demo-only             after scripts/demo.sh, install only the packages scripts/test.sh
#                           adds (scripts/setup-deps.sh packages: the armhf ones) and stop
#   --root-only             stop once the root with the skew, the user and the repository is
#                           ready (with ALE_FRESH_KEEP=1: to look around in it with chroot)
#   ALE_FRESH_DIR=DIR       work folder (default /var/tmp/ale-fresh-setup); the root is made anew
#                           in DIR/root on each run, the downloaded .debs are kept in DIR/debs
#   ALE_FRESH_LOG=FILE      the log (default DIR/fresh-setup.log)
#   ALE_FRESH_SANITIZE=1    run scripts/test.sh with the sanitizer build too (default 0: leaves
#                           out the host-asan build, which roughly doubles the time)
#   ALE_FRESH_KEEP=1        keep the root afterwards (default: removed)
# Ends with "fresh set-up: PASS" (exit 0) or "fresh set-up: FAIL ..." (exit 1).
set -euo pipefail
# One compound command: bash reads it whole before running it, so that editing this file (a
# checkout changing) while a run is under way cannot derail it.
{
repo=$(cd "$(dirname "$0")/.." && pwd)
stop=
case "${1:-}" in
  --demo-only) stop=demo ;;
  --root-only) stop=root ;;
  "") ;;
  *) echo "usage: scripts/check-fresh-setup.sh [--demo-only|--root-only]" >&2; exit 2 ;;
esac
if [ "$(id -u)" != 0 ]; then exec sudo -E "$0" "$@"; fi

work=${ALE_FRESH_DIR:-/var/tmp/ale-fresh-setup}
log=${ALE_FRESH_LOG:-$work/fresh-setup.log}
root=$work/root
user=newuser
mkdir -p "$work" "$work/debs"
exec > >(tee -a "$log") 2>&1
say() { printf '\n== %s: %s\n' "$(date -u +%H:%M:%S)" "$*"; }
fail() { printf 'fresh set-up: FAIL: %s\n' "$*"; exit 1; }

mounts=(dev/pts dev sys proc)
unmount_root() {
  local m
  for m in "${mounts[@]}"; do
    if mountpoint -q "$root/$m" 2>/dev/null; then umount -l "$root/$m"; fi
  done
}
cleanup() {
  if [ -n "${holder:-}" ]; then kill "$holder" 2>/dev/null || true; fi
  unmount_root
  if [ "${ALE_FRESH_KEEP:-0}" != 1 ] && [ -d "$root" ]; then rm -rf --one-file-system "$root"; fi
}
trap cleanup EXIT

say "check of the README's set-up on a fresh Debian 12 root ($(git -C "$repo" rev-parse --short HEAD))"
command -v debootstrap >/dev/null || { say "installing debootstrap"; apt-get install -y -q debootstrap >/dev/null; }

# This machine's mirrors: the one serving bookworm, the one serving bookworm-security.
uri_of() { # suite
  awk -v s="$1" '/^URIs:/ {u = $2} /^Suites:/ {for (i = 2; i <= NF; i++) if ($i == s) {print u; exit}}' \
    /etc/apt/sources.list.d/*.sources 2>/dev/null
}
mirror=$(uri_of bookworm); security=$(uri_of bookworm-security)
[ -n "$mirror" ] || fail "no bookworm mirror in /etc/apt/sources.list.d/*.sources"
[ -n "$security" ] || security=${mirror%/debian}/debian-security

# A root from scratch (the .debs are cached in $work/debs: the installation itself is redone).
unmount_root; rm -rf --one-file-system "$root"
say "debootstrap bookworm from $mirror"
t0=$(date +%s)
debootstrap --include=sudo,ca-certificates --cache-dir="$work/debs" bookworm "$root" "$mirror" \
  >"$work/debootstrap.log" 2>&1 || { tail -20 "$work/debootstrap.log"; fail "debootstrap failed (see $work/debootstrap.log)"; }
echo "root made in $(( $(date +%s) - t0 )) s"
rm -f "$root/etc/apt/sources.list"
cat >"$root/etc/apt/sources.list.d/debian.sources" <<SRC
Types: deb
URIs: $mirror
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: $security
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SRC
# This machine's mirror may be a snapshot whose Release files are past their Valid-Until: take
# this machine's apt settings for that.
apt-config dump | grep -E '^Acquire::(Check-Valid-Until|Check-Date) ' >"$root/etc/apt/apt.conf.d/50check-fresh-setup" || true
cp /etc/resolv.conf /etc/hosts "$root/etc/"
mount -t proc proc "$root/proc"
mount -t sysfs sys "$root/sys"
mount --bind /dev "$root/dev"
mkdir -p "$root/dev/pts"; mount --bind /dev/pts "$root/dev/pts"
in_root() { chroot "$root" /usr/bin/env -i PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 "$@"; }

# The skew: a native libpcre2-8-0 at a version the archive lacks, as on an image built from a
# newer snapshot (the armhf candidate stays 10.42-1).
say "injecting the skew: libpcre2-8-0 (native) repacked as 10.42-1+deb12u9"
pcre_deb=$(ls "$root"/var/cache/apt/archives/libpcre2-8-0_*.deb "$work"/debs/libpcre2-8-0_*.deb 2>/dev/null | head -n 1)
[ -n "$pcre_deb" ] || fail "no libpcre2-8-0 .deb from debootstrap to repack"
rm -rf "$work/repack"; mkdir -p "$work/repack"
dpkg-deb -R "$pcre_deb" "$work/repack/pkg"
sed -i 's/^Version: .*/Version: 10.42-1+deb12u9/' "$work/repack/pkg/DEBIAN/control"
dpkg-deb -b "$work/repack/pkg" "$root/tmp/libpcre2-8-0_skew.deb" >/dev/null
in_root dpkg -i /tmp/libpcre2-8-0_skew.deb >/dev/null
in_root dpkg-query -W -f='installed in the root: ${binary:Package} ${Version} (Multi-Arch: ${Multi-Arch})\n' libpcre2-8-0

# A new user with sudo, and the repository as a release would give it.
in_root useradd -m -s /bin/bash "$user"
echo "$user ALL=(ALL) NOPASSWD: ALL" >"$root/etc/sudoers.d/$user"
chmod 440 "$root/etc/sudoers.d/$user"
mkdir -p "$root/home/$user/ale-slam"
git -C "$repo" archive HEAD | tar -x -C "$root/home/$user/ale-slam"
in_root chown -R "$user:$user" "/home/$user/ale-slam"
if [ "$stop" = root ]; then echo "fresh set-up: root ready in $root"; exit 0; fi

# Another package manager holding dpkg's lock for 45 s when the set-up starts (as unattended
# upgrades do on a machine that has just booted): setup-deps.sh must wait, not fail.
say "holding dpkg's lock for 45 s (a stand-in for unattended upgrades)"
in_root perl -e 'use Fcntl; open(my $f, ">>", "/var/lib/dpkg/lock-frontend") or die;
  my $lock = pack("s s x4 q q i x4", F_WRLCK, 0, 0, 0, 0);  # struct flock on x86_64
  fcntl($f, F_SETLK, $lock) or die "lock: $!";
  $0 = "unattended-upgr"; sleep 45;' &
holder=$!
sleep 2

as_user() { # command line, run in the repository as the new user would, timed (wall and CPU:
  # on a shared machine the CPU time over the core count tells what an idle one would take)
  local t=$(date +%s) rc=0 cpu0 cpu1 me=$BASHPID
  cpu0=$(awk '{print $14 + $15 + $16 + $17}' "/proc/$me/stat")
  in_root su - "$user" -c "cd ale-slam && $*" || rc=$?
  cpu1=$(awk '{print $14 + $15 + $16 + $17}' "/proc/$me/stat")
  echo "($* : exit $rc after $(( $(date +%s) - t )) s, $(( (cpu1 - cpu0) / $(getconf CLK_TCK) )) s of CPU on $(nproc) cores)"
  return $rc
}
say "README command 1: scripts/demo.sh"
as_user scripts/demo.sh || fail "scripts/demo.sh failed"
wait "$holder" 2>/dev/null || true; holder=
if [ "$stop" = demo ]; then
  # the first step of scripts/test.sh without its builds: the armhf packages, where the skew bites
  say "scripts/test.sh's package step: scripts/setup-deps.sh packages"
  as_user scripts/setup-deps.sh packages || fail "scripts/setup-deps.sh packages failed"
  echo "fresh set-up: PASS (scripts/demo.sh and the armhf packages only)"
  exit 0
fi
say "README command 2: scripts/test.sh (ALE_SANITIZE=${ALE_FRESH_SANITIZE:-0})"
out=$(mktemp)
as_user "ALE_SANITIZE=${ALE_FRESH_SANITIZE:-0} scripts/test.sh" | tee "$out" || { tail -1 "$out"; fail "scripts/test.sh failed"; }
# test.sh's summary line (as_user's timing line follows it)
summary=$(grep -E '^[0-9]+ passed, [0-9]+ failed' "$out" | tail -n 1)
[[ $summary =~ ^[0-9]+\ passed,\ 0\ failed ]] || fail "scripts/test.sh: ${summary:-no summary line}"
rm -f "$out"
echo "fresh set-up: PASS"
exit 0
}
