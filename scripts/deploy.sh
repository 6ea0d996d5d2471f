#!/usr/bin/env bash
# Installs ale-slamd on a running board: the stripped static armhf daemon, the procd init script,
# the configuration and the camera calibration, then restarts the service.
#
#   scripts/deploy.sh [options] HOST          over ssh (HOST as ssh takes it: user@ip, an alias)
#   scripts/deploy.sh --adb [options] [SERIAL] over adb (the first device when no serial)
#
# Options:
#   --binary PATH        the armhf daemon (default: build/armhf/bin/ale-slamd)
#   --config FILE        the configuration to install (default: board/mr133/ale-slamd.conf)
#   --calibration FILE   a camera calibration to install as /etc/ale-slam/calibration.yaml
#   --force-config       replace the board's configuration (and calibration) if it has one;
#                        without it the board's own files are kept
#   --no-restart         do not enable/restart the service
#   --dry-run            print what would be done, change nothing
# Exit status: 0 installed, 1 a step failed (the message names it), 2 bad arguments.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
board=$root/board/mr133
say() { printf 'deploy: %s\n' "$*" >&2; }
die() { printf 'deploy: error: %s\n' "$*" >&2; exit 1; }
usage() { sed -n '2,17s/^# \{0,1\}//p' "$0" >&2; exit 2; }

transport=ssh host= binary=$root/build/armhf/bin/ale-slamd config=$board/ale-slamd.conf calibration=
force=0 restart=1 dry=0
while [ $# -gt 0 ]; do
  case "$1" in
    --adb) transport=adb ;;
    --binary) binary=${2:?--binary needs a path}; shift ;;
    --config) config=${2:?--config needs a file}; shift ;;
    --calibration) calibration=${2:?--calibration needs a file}; shift ;;
    --force-config) force=1 ;;
    --no-restart) restart=0 ;;
    --dry-run) dry=1 ;;
    -h|--help) usage ;;
    -*) say "unknown option $1"; usage ;;
    *) [ -z "$host" ] || { say "more than one host: $host, $1"; usage; }; host=$1 ;;
  esac
  shift
done
[ "$transport" = adb ] || [ -n "$host" ] || { say "no host given"; usage; }

[ -f "$binary" ] || die "no daemon at $binary (build it: scripts/build.sh armhf)"
file -b "$binary" | grep -q 'ARM' || die "$binary is not an ARM executable ($(file -b "$binary" | cut -c1-60))"
file -b "$binary" | grep -q 'statically linked' || die "$binary is not statically linked: the board has no libraries for it"
[ -f "$config" ] || die "no configuration at $config"
[ -z "$calibration" ] || [ -f "$calibration" ] || die "no calibration at $calibration"

stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
install -d "$stage/usr/bin" "$stage/etc/init.d" "$stage/etc/ale-slam"
cp "$binary" "$stage/usr/bin/ale-slamd"
strip=arm-linux-gnueabihf-strip
command -v "$strip" >/dev/null || die "$strip not found (install binutils-arm-linux-gnueabihf)"
"$strip" "$stage/usr/bin/ale-slamd" || die "cannot strip $binary"
chmod 0755 "$stage/usr/bin/ale-slamd"
install -m 0755 "$board/ale-slamd.init" "$stage/etc/init.d/ale-slamd"
install -m 0644 "$config" "$stage/etc/ale-slam/ale-slamd.conf"
[ -z "$calibration" ] || install -m 0644 "$calibration" "$stage/etc/ale-slam/calibration.yaml"
say "daemon $(stat -c %s "$stage/usr/bin/ale-slamd") bytes stripped"

# remote_sh CMD: runs a shell command on the board; push SRC DST: copies one file there.
if [ "$transport" = adb ]; then
  adb_=(adb); [ -z "$host" ] || adb_+=(-s "$host")
  remote_sh() { "${adb_[@]}" shell "$1"; }
  push() { "${adb_[@]}" push "$1" "$2" >/dev/null; }
  where="adb${host:+ device $host}"
else
  remote_sh() { ssh -o BatchMode=yes -o ConnectTimeout=10 "$host" "$1"; }
  push() { scp -q -o BatchMode=yes -o ConnectTimeout=10 "$1" "$host:$2"; }
  where=$host
fi
run() {
  if [ "$dry" = 1 ]; then say "would run on $where: $*"; else "$@"; fi
}

remote_sh 'echo ok' >/dev/null 2>&1 || die "cannot reach the board ($where)"
arch=$(remote_sh 'uname -m' 2>/dev/null | tr -d '\r')
case "$arch" in armv7*|armv8*|aarch64) ;; *) die "the board at $where reports machine '$arch', not ARMv7" ;; esac

keep_config=0
if [ "$force" = 0 ] && remote_sh 'test -f /etc/ale-slam/ale-slamd.conf' 2>/dev/null; then
  keep_config=1
  say "keeping the board's /etc/ale-slam/ale-slamd.conf (--force-config replaces it)"
fi
keep_calibration=0
if [ -n "$calibration" ] && [ "$force" = 0 ] && remote_sh 'test -f /etc/ale-slam/calibration.yaml' 2>/dev/null; then
  keep_calibration=1
  say "keeping the board's /etc/ale-slam/calibration.yaml (--force-config replaces it)"
fi

run remote_sh 'mkdir -p /usr/bin /etc/init.d /etc/ale-slam' || die "cannot create folders on the board"
# The daemon goes in under a temporary name and is renamed over the old one, so a failed copy
# never leaves the board without a working binary.
run push "$stage/usr/bin/ale-slamd" /usr/bin/ale-slamd.new || die "copying the daemon failed"
run remote_sh 'chmod 0755 /usr/bin/ale-slamd.new && mv /usr/bin/ale-slamd.new /usr/bin/ale-slamd' ||
  die "installing the daemon failed"
run push "$stage/etc/init.d/ale-slamd" /etc/init.d/ale-slamd || die "copying the init script failed"
run remote_sh 'chmod 0755 /etc/init.d/ale-slamd' || die "chmod of the init script failed"
if [ "$keep_config" = 0 ]; then
  run push "$stage/etc/ale-slam/ale-slamd.conf" /etc/ale-slam/ale-slamd.conf || die "copying the configuration failed"
fi
if [ -n "$calibration" ] && [ "$keep_calibration" = 0 ]; then
  run push "$stage/etc/ale-slam/calibration.yaml" /etc/ale-slam/calibration.yaml || die "copying the calibration failed"
fi
run remote_sh '/usr/bin/ale-slamd --version' >/dev/null || die "the installed daemon does not run on the board"
if [ "$restart" = 1 ]; then
  run remote_sh '/etc/init.d/ale-slamd enable; /etc/init.d/ale-slamd restart' || die "restarting the service failed"
fi
say "installed on $where"
