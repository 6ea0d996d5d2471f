#!/usr/bin/env bash
# Tracking through turns on the spot, blackouts, kidnaps and repeated rooms (issue 31): renders a
# suite of sequences, replays each with ale-slamd and prints one table (docs/evaluation.md).
#
#   scripts/place-bench.sh [--quick] [--out DIR] [--jobs N] [--render-only] [--only NAME]...
#
#   --quick        four sequences (lanes, square at 90 deg/s, a blackout, a kidnap): under five
#                  minutes of replay once rendered
#   --out DIR      renders in DIR/renders (kept: a second run renders only what is missing or
#                  whose options changed), runs in DIR/runs (default /tmp/ale-place-bench)
#   --jobs N       renders at a time (default 2)
#   --render-only  render the suite and stop
#   --only NAME    just this sequence (may be repeated)
# Settings (environment): BIN (default build/host/bin: ale-render, ale-slamd, ale-eval), SLAMD_ARGS
# (extra ale-slamd arguments, e.g. "--set slam.x=y").
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
bench=place-bench
out=/tmp/ale-place-bench
render_base="--fps 15 --width 640 --height 480 --seed 1"
max_jobs=
# shellcheck source=bench-lib.sh
. "$root/scripts/bench-lib.sh"
parse_bench_args "$@"

# The suite: name | quick (1 = in --quick) | event (blackout:S,D or kidnap:A,T,G or -) | ale-render
# options. All at 640x480, 15 fps, supersample 2, sensor seed 1; events are also passed to
# ale-render. Rooms: the living room (6 x 5 m) and halls of other sizes and texture seeds.
suite() {
  cat <<'EOF'
lanes_living_w30_t60|1|-|--trajectory lanes --lane-width 0.3 --turn-rate 60 --duration 60
lanes_living_w30_t90_dark|0|-|--trajectory lanes --lane-width 0.3 --turn-rate 90 --light dark --duration 60
lanes_hall8x6_w50_t90|0|-|--trajectory lanes --room 8x6x2.6 --texture-seed 11 --lanes 5 --lane-width 0.5 --lane-length 5 --turn-rate 90 --duration 60
lanes_hall10x7_w40_t60_dark|0|-|--trajectory lanes --room 10x7x2.8 --texture-seed 23 --lane-width 0.4 --lane-length 6 --turn-rate 60 --light dark --duration 60
lanes_hall7x5_w30_t90|0|-|--trajectory lanes --room 7x5x2.5 --texture-seed 37 --lane-width 0.3 --lane-length 4 --turn-rate 90 --duration 60
square_t60|0|-|--trajectory square --turn-rate 60 --duration 45
square_t90|1|-|--trajectory square --turn-rate 90 --duration 45
loop|0|-|--trajectory loop --duration 40
loop_blackout2s|1|blackout:20,2|--trajectory loop --duration 40
loop_kidnap|1|kidnap:30,8,3|--trajectory loop --duration 45
twin_rooms|0|-|--scene twin --duration 90
EOF
}

render_suite
replay_and_table place-bench-eval.py
exit $failed
