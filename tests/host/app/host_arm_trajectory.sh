#!/usr/bin/env bash
# The armhf daemon under qemu-arm and the host's daemon replay the same short rendered sequences
# and must write byte-identical trajectory files (the SLAM core is deterministic across the two:
# Eigen is scalar on x86 too, CMakeLists.txt says why). Two sequences: 90 frames of the default
# loop in normal light, 60 frames of the square route in dark light (measured identical, 85 and
# 55 tracked frames). Run from the armhf build (ctest); the host's binaries come from build/host.
#   host_arm_trajectory.sh WORKDIR ARM_SLAMD HOST_BIN_DIR EMULATOR...
# A missing host build is a skip, or a failure with CI=true.
set -euo pipefail
work=$1 arm_slamd=$2 host_bin=$3
shift 3
emulator=("$@")
fail() { echo "FAIL: $*" >&2; exit 1; }
for tool in ale-slamd ale-render; do
  if [ ! -x "$host_bin/$tool" ]; then
    [ "${CI:-}" = true ] && fail "CI=true but the host build's $tool is missing ($host_bin)"
    echo "ALE_SKIP: the host build's $tool is missing ($host_bin): build the host first"
    exit 0
  fi
done
rm -rf "$work"
mkdir -p "$work"
compare() {  # NAME FRAMES RENDER_ARGS...
  local name=$1 frames=$2
  shift 2
  "$host_bin/ale-render" --out "$work/$name" --frames "$frames" --fps 15 --supersample 1 --seed 5 "$@" >/dev/null
  "$host_bin/ale-slamd" --replay "$work/$name" --lcm-url memq:// --trajectory "$work/$name.host.tum" 2>"$work/$name.host.log" ||
    { cat "$work/$name.host.log"; fail "$name: the host daemon exited with $?"; }
  "${emulator[@]}" "$arm_slamd" --replay "$work/$name" --lcm-url memq:// --trajectory "$work/$name.arm.tum" \
    2>"$work/$name.arm.log" || { cat "$work/$name.arm.log"; fail "$name: the armhf daemon exited with $?"; }
  local poses
  poses=$(grep -vc '^#' "$work/$name.host.tum" || true)
  # identical empty files prove nothing: most frames must have a pose
  [ "$poses" -ge $((frames * 2 / 3)) ] || fail "$name: $poses poses in $frames frames"
  if ! cmp -s "$work/$name.host.tum" "$work/$name.arm.tum"; then
    # say how far apart they are before failing
    paste -d' ' <(grep -v '^#' "$work/$name.host.tum") <(grep -v '^#' "$work/$name.arm.tum") |
      awk '{ for (i = 1; i <= 8; ++i) { d = $i - $(i + 8); if (d < 0) d = -d; if (d > m) { m = d; at = NR } } }
           END { printf "largest difference %g (line %d)\n", m, at }'
    diff "$work/$name.host.tum" "$work/$name.arm.tum" | head -n 6
    fail "$name: the host and armhf trajectories differ"
  fi
  echo "$name: host and armhf trajectories identical, $poses poses of $frames frames"
}
compare loop_normal 90
compare square_dark 60 --trajectory square --light dark
echo "host_arm_trajectory: PASS"
