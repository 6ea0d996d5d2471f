#!/usr/bin/env bash
# A fake board for deploy_test.sh: stands in for ssh, scp and adb (by the name it is called
# under), maps the board's / to $FAKE_BOARD_ROOT, and logs every call to $FAKE_BOARD_ROOT/calls.
set -euo pipefail
r=${FAKE_BOARD_ROOT:?}
me=$(basename "$0")
echo "$me $*" >> "$r/calls"
map() { sed -e "s#\(^\|[ ;&]\)/usr/#\1$r/usr/#g" -e "s#\(^\|[ ;&]\)/etc/#\1$r/etc/#g" <<<"$1"; }
board_sh() {
  local cmd=$1
  case "$cmd" in
    'uname -m') echo armv7l; return ;;
    '/usr/bin/ale-slamd --version') ${FAKE_BOARD_EMULATOR:-} "$r/usr/bin/ale-slamd" --version; return ;;
    *'/etc/init.d/ale-slamd enable'*) echo "service restarted" >> "$r/service"; return ;;
  esac
  sh -c "$(map "$cmd")"
}
case "$me" in
  ssh)
    while [ $# -gt 0 ] && [ "$1" = -o ]; do shift 2; done
    [ "${FAKE_BOARD_UNREACHABLE:-0}" = 1 ] && exit 255
    shift  # host
    board_sh "$1" ;;
  scp)
    while [ $# -gt 0 ] && { [ "$1" = -o ] || [ "$1" = -q ]; }; do [ "$1" = -o ] && shift; shift; done
    cp "$1" "$r${2#*:}" ;;
  adb)
    [ "$1" = -s ] && shift 2
    case "$1" in
      shell) board_sh "$2" ;;
      push) cp "$2" "$r$3" ;;
    esac ;;
esac
