#!/bin/sh
# Lays out the files for the board's root filesystem under DESTDIR (a staging folder that the
# Tina build or a tarball picks up):
#   board/mr133/install.sh DESTDIR [path/to/armhf/ale-slamd]
set -eu
dest=${1:?usage: install.sh DESTDIR [ale-slamd binary]}
here=$(cd "$(dirname "$0")" && pwd)
bin=${2:-$here/../../build/armhf/bin/ale-slamd}
[ -x "$bin" ] || { echo "install.sh: no armhf ale-slamd at $bin (run scripts/build.sh armhf)" >&2; exit 1; }
install -d "$dest/usr/bin" "$dest/etc/init.d" "$dest/etc/ale-slam"
install -m 0755 "$bin" "$dest/usr/bin/ale-slamd"
arm-linux-gnueabihf-strip "$dest/usr/bin/ale-slamd" 2>/dev/null || true
install -m 0755 "$here/ale-slamd.init" "$dest/etc/init.d/ale-slamd"
[ -f "$dest/etc/ale-slam/ale-slamd.conf" ] || install -m 0644 "$here/ale-slamd.conf" "$dest/etc/ale-slam/ale-slamd.conf"
install -m 0644 "$here/calibration.example.yaml" "$dest/etc/ale-slam/calibration.example.yaml"
echo "installed into $dest"
