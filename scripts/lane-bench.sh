#!/usr/bin/env bash
# Cleaning lanes, camera alone by default (issue 31): renders twelve one-lap lane routes (four
# lanes, 90-degree turns on the spot at 60-90 deg/s, lane widths 0.3-0.5 m, six rooms from 6 x 5 to
# 12 x 8 m) at 320x240, replays each with ale-slamd and prints one table with the mean and median
# ATE; with --baseline, each route against an earlier run of the bench (better / worse, sign test).
# A single route swings 2-8x with any change (docs/slam.md), so compare over all twelve.
#
#   scripts/lane-bench.sh [--quick] [--out DIR] [--jobs N] [--render-only] [--only NAME]...
#                         [--baseline RUNS] [--light P] [--resolution WxH]
#
#   --quick        four routes (one per turn rate and the largest room): about 3700 frames to
#                  render once, under a minute of replay
#   --out DIR      renders in DIR/renders (kept: a second run renders only what is missing or
#                  whose options changed), runs in DIR/runs (default /tmp/ale-lane-bench)
#   --jobs N       renders at a time (default 2)
#   --render-only  render the suite and stop
#   --only NAME    just this route (may be repeated)
#   --baseline RUNS  the runs folder of an earlier lane-bench (another build or settings, the same
#                  renders): per route its ATE beside this one's, and the paired comparison
#   --light P      every route in ale-render's light profile P (dark, normal_dark, ...), named
#                  NAME_P; default normal, as named
#   --resolution WxH  every route at W x H pixels (the sweeper's camera is 640x480), named NAME_WxH;
#                  default 320x240, as named
# Settings (environment): BIN (default build/host/bin: ale-render, ale-slamd, ale-eval), SLAMD_ARGS
# (ale-slamd arguments; default --no-odometry, the camera alone; SLAMD_ARGS= for the camera with
# the renders' wheel odometry).
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
bench=lane-bench
out=/tmp/ale-lane-bench
max_jobs=
SLAMD_ARGS=${SLAMD_ARGS---no-odometry}
baseline=
light=normal
resolution=320x240
args=()
while [ $# -gt 0 ]; do
  if [ "$1" = --baseline ] || [ "$1" = --light ] || [ "$1" = --resolution ]; then
    [ $# -ge 2 ] || { echo "$bench: $1 needs a value" >&2; exit 2; }
    case $1 in
      --baseline) baseline=$2 ;;
      --light) light=$2 ;;
      *) resolution=$2 ;;
    esac
    shift 2
  else
    args+=("$1")
    shift
  fi
done
[[ $resolution =~ ^([0-9]+)x([0-9]+)$ ]] || { echo "$bench: --resolution: WxH, not $resolution" >&2; exit 2; }
render_base="--trajectory lanes --lanes 4 --laps 1 --fps 15 --width ${BASH_REMATCH[1]} --height ${BASH_REMATCH[2]} --supersample 1"
# shellcheck source=bench-lib.sh
. "$root/scripts/bench-lib.sh"
parse_bench_args "${args[@]}"
[ -z "$baseline" ] || [ -d "$baseline" ] || die "--baseline: no folder $baseline"

# The suite: name (room, lane width in cm, turn rate in deg/s) | quick | event (none) | ale-render
# options (room, textures, lane width and length, turn rate, sensor seed); with --light P each
# name gains _P and each route --light P; with --resolution WxH (not 320x240) _WxH.
suite() {
  local suffix="" extra=""
  [ "$light" = normal ] || { suffix="_$light"; extra=" --light $light"; }
  [ "$resolution" = 320x240 ] || suffix="${suffix}_$resolution"
  routes | sed "s/^\([^|]*\)\(|.*\)$/\1$suffix\2$extra/"
}
routes() {
  cat <<'EOF2'
lanes_6x5_w30_t60|1|-|--room 6x5x2.5 --texture-seed 3 --lane-width 0.3 --lane-length 3 --turn-rate 60 --seed 1
lanes_6x5_w40_t90|1|-|--room 6x5x2.5 --texture-seed 3 --lane-width 0.4 --lane-length 3 --turn-rate 90 --seed 2
lanes_8x6_w50_t90|0|-|--room 8x6x2.6 --texture-seed 11 --lane-width 0.5 --lane-length 4 --turn-rate 90 --seed 3
lanes_8x6_w30_t60|0|-|--room 8x6x2.6 --texture-seed 12 --lane-width 0.3 --lane-length 4 --turn-rate 60 --seed 4
lanes_10x7_w40_t60|0|-|--room 10x7x2.8 --texture-seed 23 --lane-width 0.4 --lane-length 5 --turn-rate 60 --seed 5
lanes_10x7_w50_t90|0|-|--room 10x7x2.8 --texture-seed 24 --lane-width 0.5 --lane-length 5 --turn-rate 90 --seed 6
lanes_7x5_w30_t90|0|-|--room 7x5x2.5 --texture-seed 37 --lane-width 0.3 --lane-length 4 --turn-rate 90 --seed 7
lanes_7x5_w40_t60|0|-|--room 7x5x2.5 --texture-seed 38 --lane-width 0.4 --lane-length 3.5 --turn-rate 60 --seed 8
lanes_9x6_w35_t75|1|-|--room 9x6x2.7 --texture-seed 41 --lane-width 0.35 --lane-length 4.5 --turn-rate 75 --seed 9
lanes_9x6_w45_t90|0|-|--room 9x6x2.7 --texture-seed 42 --lane-width 0.45 --lane-length 4 --turn-rate 90 --seed 10
lanes_6x6_w30_t75|0|-|--room 6x6x2.5 --texture-seed 51 --lane-width 0.3 --lane-length 3.5 --turn-rate 75 --seed 11
lanes_12x8_w50_t60|1|-|--room 12x8x3 --texture-seed 61 --lane-width 0.5 --lane-length 6 --turn-rate 60 --seed 12
EOF2
}

render_suite
[ -z "$baseline" ] || table_args=(--baseline "$baseline")
replay_and_table lane-bench-eval.py
exit $failed
