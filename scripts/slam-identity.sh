#!/usr/bin/env bash
# Renders the sequences that a behaviour-neutral change of the SLAM core must replay to the same
# bytes, and replays them: a loop in normal light, the same in the dark, a loop with the lights
# switched off and on, a square with turns on the spot, and cleaning lanes (turns on the spot).
#
#   scripts/slam-identity.sh render RENDERS            render once (about 2 minutes on 2 cores)
#   scripts/slam-identity.sh replay RENDERS OUT        replay each with BIN's ale-slamd into OUT/NAME.tum
#   scripts/slam-identity.sh compare OUT_A OUT_B       cmp every trajectory; exit 1 on any difference
#
# BIN (default build/host/bin) holds ale-slamd and ale-render; QEMU (e.g. qemu-arm-static) runs BIN's
# ale-slamd through it (BIN=build/armhf/bin QEMU=qemu-arm-static: the armhf build under emulation).
# SLAMD_ARGS: extra ale-slamd arguments. ale-render writes wheel odometry with every sweeper route,
# so renders made now replay fused; SLAMD_ARGS=--no-odometry replays them on vision alone, the
# same bytes as renders made before the odometry (the frames are the same).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
BIN=${BIN:-$root/build/host/bin}
QEMU=${QEMU:-}
die() { echo "slam-identity: $*" >&2; exit 2; }

# name: ale-render arguments
sequences() {
  cat <<'SEQ'
normal --trajectory loop --frames 300 --fps 15 --light normal --seed 1
dark --trajectory loop --frames 300 --fps 15 --light dark --seed 2
off_on --trajectory loop --frames 300 --fps 15 --light off_on --seed 3
square --trajectory square --frames 450 --fps 15 --light normal --seed 4
lanes --trajectory lanes --frames 600 --fps 15 --light normal --seed 5
SEQ
}

case "${1:-}" in
  render)
    [ $# -eq 2 ] || die "usage: render RENDERS"
    mkdir -p "$2"
    sequences | while read -r name args; do
      [ -f "$2/$name/mav0/cam0/data.csv" ] && continue
      # shellcheck disable=SC2086
      "$BIN/ale-render" --out "$2/$name" $args --overwrite >/dev/null || die "render of $name failed"
      echo "rendered $2/$name"
    done ;;
  replay)
    [ $# -eq 3 ] || die "usage: replay RENDERS OUT"
    mkdir -p "$3"
    sequences | while read -r name _; do
      [ -d "$2/$name" ] || die "$2/$name is missing: run render first"
      # shellcheck disable=SC2086  # SLAMD_ARGS are words
      $QEMU "$BIN/ale-slamd" --replay "$2/$name" --lcm-url memq:// --trajectory "$3/$name.tum" ${SLAMD_ARGS:-} \
        --frame-log "$3/$name.frames.csv" >"$3/$name.log" 2>&1 || die "replay of $name failed (see $3/$name.log)"
      echo "$name: $(grep -vc '^#' "$3/$name.tum") poses"
    done ;;
  compare)
    [ $# -eq 3 ] || die "usage: compare OUT_A OUT_B"
    differ=0
    sequences | while read -r name _; do
      if cmp -s "$2/$name.tum" "$3/$name.tum"; then echo "$name: identical"; else echo "$name: DIFFERENT"; exit 1; fi
    done || differ=1
    exit $differ ;;
  *) die "usage: scripts/slam-identity.sh render RENDERS | replay RENDERS OUT | compare OUT_A OUT_B" ;;
esac
