#!/usr/bin/env bash
# scripts/deploy.sh against a fake board (fake_board.sh as ssh/scp/adb): installs the daemon,
# init script and configuration, keeps the board's configuration unless --force-config, refuses
# a host daemon and an unreachable board.
#   deploy_test.sh REPO ARMHF_DAEMON [EMULATOR]
set -uo pipefail
repo=$1 daemon=$2 emu=${3:-}
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
mkdir -p "$work/bin" "$work/board"
for t in ssh scp adb; do ln -s "$repo/tests/host/scripts/fake_board.sh" "$work/bin/$t"; done
export PATH=$work/bin:$PATH FAKE_BOARD_ROOT=$work/board FAKE_BOARD_EMULATOR=$emu
fail=0
check() { if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1"; fail=1; fi; }

"$repo/scripts/deploy.sh" --binary "$daemon" robot >"$work/out1" 2>&1; rc=$?
cat "$work/out1"
check "first install exits 0" "[ $rc = 0 ]"
check "daemon installed and stripped" "[ -x $work/board/usr/bin/ale-slamd ] && file -b $work/board/usr/bin/ale-slamd | grep -q 'stripped' && ! file -b $work/board/usr/bin/ale-slamd | grep -q 'not stripped'"
check "init script installed" "[ -x $work/board/etc/init.d/ale-slamd ]"
check "configuration installed" "cmp -s $repo/board/mr133/ale-slamd.conf $work/board/etc/ale-slam/ale-slamd.conf"
check "service restarted" "grep -q restarted $work/board/service"
check "no temporary binary left" "[ ! -e $work/board/usr/bin/ale-slamd.new ]"

echo "# edited on the board" >> "$work/board/etc/ale-slam/ale-slamd.conf"
cp "$work/board/etc/ale-slam/ale-slamd.conf" "$work/edited.conf"
echo "calib: 1" > "$work/calib.yaml"
"$repo/scripts/deploy.sh" --binary "$daemon" --calibration "$work/calib.yaml" robot >"$work/out2" 2>&1; rc=$?
check "second install exits 0" "[ $rc = 0 ]"
check "board configuration kept" "cmp -s $work/edited.conf $work/board/etc/ale-slam/ale-slamd.conf"
check "keeping is reported" "grep -q 'keeping the board' $work/out2"
check "calibration installed" "cmp -s $work/calib.yaml $work/board/etc/ale-slam/calibration.yaml"

"$repo/scripts/deploy.sh" --adb --force-config --binary "$daemon" >"$work/out3" 2>&1; rc=$?
check "adb --force-config exits 0" "[ $rc = 0 ]"
check "configuration replaced" "cmp -s $repo/board/mr133/ale-slamd.conf $work/board/etc/ale-slam/ale-slamd.conf"
check "adb was used" "grep -q '^adb push' $work/board/calls"

"$repo/scripts/deploy.sh" --binary /bin/sh robot >"$work/out4" 2>&1; rc=$?
check "a host binary is refused with 1" "[ $rc = 1 ] && grep -q 'not an ARM executable' $work/out4"
FAKE_BOARD_UNREACHABLE=1 "$repo/scripts/deploy.sh" --binary "$daemon" robot >"$work/out5" 2>&1; rc=$?
check "an unreachable board fails with 1" "[ $rc = 1 ] && grep -q 'cannot reach the board' $work/out5"
"$repo/scripts/deploy.sh" --binary "$daemon" >"$work/out6" 2>&1; rc=$?
check "no host is a usage error (2)" "[ $rc = 2 ]"
[ $fail = 0 ] && echo "deploy_test: all passed"
exit $fail
