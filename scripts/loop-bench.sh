#!/usr/bin/env bash
# Loop closing and map merging (issue 32): renders routes driven several times (ale-render
# --laps), a run that starts a second map and comes back to the first's places, and the twin rooms;
# replays each with ale-slamd and prints one table (docs/evaluation.md).
#
#   scripts/loop-bench.sh [--quick] [--out DIR] [--jobs N] [--render-only] [--only NAME]...
#
#   --quick        four routes (the loop twice, the lanes twice, the merge, the twin rooms): about
#                  4200 frames to render once, two minutes of replay
#   --out DIR      renders in DIR/renders (kept: a second run renders only what is missing or
#                  whose options changed), runs in DIR/runs (default /tmp/ale-loop-bench)
#   --jobs N       renders at a time (default 2)
#   --render-only  render the suite and stop
#   --only NAME    just this route (may be repeated)
# Settings (environment): BIN (default build/host/bin: ale-render, ale-slamd, ale-eval), SLAMD_ARGS
# (extra ale-slamd arguments, e.g. "--set slam.x=y").
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
bench=loop-bench
out=/tmp/ale-loop-bench
render_base="--fps 15 --width 640 --height 480"
max_jobs=
# shellcheck source=bench-lib.sh
. "$root/scripts/bench-lib.sh"
parse_bench_args "$@"

# The suite: name | quick (1 = in --quick) | event (blackout:S,D or -) | ale-render options. All
# at 640x480, 15 fps, supersample 2. Rooms: the living room (6 x 5 m) and halls of other sizes and
# texture seeds; sensor seeds 1-4. The loop's lap is 26.4 s (7.9 m). merge_*: the light goes off
# 8 s in for 10 s and comes back 5.4 m along the loop, facing walls the first map never saw; the
# second lap drives through the first map's places again (merge_lanes_*: the light goes off 12 s
# into the first pass over the lanes, the second pass drives them again).
suite() {
  cat <<'EOF'
loop_living_x2|1|-|--trajectory loop --laps 2 --seed 1
loop_living_x3|0|-|--trajectory loop --laps 3 --seed 2
loop_living_x2_dark|0|-|--trajectory loop --laps 2 --light dark --seed 1
loop_hall8x6_x2|0|-|--trajectory loop --room 8x6x2.6 --texture-seed 11 --laps 2 --seed 3
loop_hall7x5_x3|0|-|--trajectory loop --room 7x5x2.5 --texture-seed 37 --laps 3 --seed 4
loop_hall10x7_x2_dark|0|-|--trajectory loop --room 10x7x2.8 --texture-seed 23 --laps 2 --light dark --seed 2
lanes_living_x2|1|-|--trajectory lanes --lanes 4 --lane-width 0.4 --lane-length 2 --turn-rate 90 --laps 2 --seed 1
lanes_hall8x6_x2|0|-|--trajectory lanes --room 8x6x2.6 --texture-seed 11 --lanes 4 --lane-width 0.5 --lane-length 3 --turn-rate 90 --laps 2 --seed 3
merge_loop_living_x2|1|blackout:8,10|--trajectory loop --laps 2 --seed 1
merge_loop_hall8x6_x3_dark|0|blackout:8,10|--trajectory loop --room 8x6x2.6 --texture-seed 11 --laps 3 --light dark --seed 3
merge_lanes_hall8x6_x2|0|blackout:12,10|--trajectory lanes --room 8x6x2.6 --texture-seed 11 --lanes 4 --lane-width 0.5 --lane-length 3 --turn-rate 90 --laps 2 --seed 2
twin_rooms|1|-|--scene twin --duration 90 --seed 1
EOF
}

render_suite
replay_and_table loop-bench-eval.py
exit $failed
