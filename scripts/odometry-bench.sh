#!/usr/bin/env bash
# Metric poses from wheel odometry (issue 34): renders sweeper routes with odometry, and for each
# scores the odometry alone, the camera alone (--no-odometry) and the two fused, in one table
# (docs/evaluation.md, "Odometry bench").
#
#   scripts/odometry-bench.sh [--quick] [--out DIR] [--jobs N] [--render-only] [--only NAME]...
#
#   --quick        three sequences (a square at 90 deg/s, a loop with harsh odometry, the loop with
#                  a 2 s blackout): about 4 minutes of replay once rendered
#   --out DIR      renders in DIR/renders (kept: a second run renders only what is missing or
#                  whose options changed), runs in DIR/runs (default /tmp/ale-odometry-bench)
#   --jobs N       renders and replays at a time (default 2, at most 2)
#   --render-only  render the suite and stop
#   --only NAME    just this sequence (may be repeated)
# Settings (environment): BIN (default build/host/bin: ale-render, ale-slamd, ale-eval), SLAMD_ARGS
# (extra ale-slamd arguments for both replays, e.g. "--set slam.x=y").
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
bench=odometry-bench
out=/tmp/ale-odometry-bench
render_base="--fps 15 --width 640 --height 480"
max_jobs=2
# shellcheck source=bench-lib.sh
. "$root/scripts/bench-lib.sh"
parse_bench_args "$@"

# The suite: name | quick (1 = in --quick) | event (blackout:S,D or -) | ale-render options. All at
# 640x480, 15 fps, supersample 2; odometry at 50 Hz, noise `normal` unless the name says harsh.
# The lane rooms are place-bench's (the living room 6 x 5 m and three halls).
suite() {
  cat <<'EOF2'
lanes_living_w30_t60|0|-|--seed 1 --trajectory lanes --lane-width 0.3 --turn-rate 60 --duration 60
lanes_living_w30_t90_dark|0|-|--seed 1 --trajectory lanes --lane-width 0.3 --turn-rate 90 --light dark --duration 60
lanes_hall8x6_w50_t90|0|-|--seed 1 --trajectory lanes --room 8x6x2.6 --texture-seed 11 --lanes 5 --lane-width 0.5 --lane-length 5 --turn-rate 90 --duration 60
lanes_hall8x6_w50_t90_harsh|0|-|--seed 1 --trajectory lanes --room 8x6x2.6 --texture-seed 11 --lanes 5 --lane-width 0.5 --lane-length 5 --turn-rate 90 --duration 60 --odometry-noise harsh
lanes_hall10x7_w40_t60_dark|0|-|--seed 1 --trajectory lanes --room 10x7x2.8 --texture-seed 23 --lane-width 0.4 --lane-length 6 --turn-rate 60 --light dark --duration 60
lanes_hall7x5_w30_t90|0|-|--seed 1 --trajectory lanes --room 7x5x2.5 --texture-seed 37 --lane-width 0.3 --lane-length 4 --turn-rate 90 --duration 60
lanes_hall7x5_w30_t90_off_on|0|-|--seed 3 --trajectory lanes --room 7x5x2.5 --texture-seed 37 --lane-width 0.3 --lane-length 4 --turn-rate 90 --light off_on --duration 60
square_t60|0|-|--seed 1 --trajectory square --turn-rate 60 --duration 45
square_t90|1|-|--seed 1 --trajectory square --turn-rate 90 --duration 45
square_t90_seed2|0|-|--seed 2 --odometry-seed 2 --trajectory square --turn-rate 90 --duration 45
square_t90_dark_harsh|0|-|--seed 1 --trajectory square --turn-rate 90 --light dark --duration 45 --odometry-noise harsh
square_t60_sunlit|0|-|--seed 4 --trajectory square --turn-rate 60 --light sunlit --duration 45
loop|0|-|--seed 1 --trajectory loop --duration 40
loop_seed2|0|-|--seed 2 --odometry-seed 2 --trajectory loop --duration 40
loop_harsh|1|-|--seed 1 --trajectory loop --duration 40 --odometry-noise harsh
loop_blackout2s|1|blackout:20,2|--seed 1 --trajectory loop --duration 40
EOF2
}

render_suite
mapfile -t names < <(selected_names)

# replay NAME MODE [ale-slamd options]: DIR/runs/NAME.MODE.{tum,frames.csv,log}.
replay() {
  local name=$1 mode=$2 run=$out/runs/$1.$2
  shift 2
  # shellcheck disable=SC2086  # SLAMD_ARGS are words
  if ! "$BIN/ale-slamd" --replay "$out/renders/$name" --lcm-url memq:// --trajectory "$run.tum" \
       --frame-log "$run.frames.csv" "$@" $SLAMD_ARGS > "$run.log" 2>&1; then
    echo "replay $name ($mode): FAILED (see $run.log)" >&2
    return 1
  fi
  echo "replay $name ($mode): $(grep -Eo 'frames [0-9]+ tracked [0-9]+' "$run.log" | tail -1)"
}

# Replays: the camera alone and fused; a blackout's fused run writes the odometry-propagated poses
# of lost frames too (daemon.trajectory_poses=online). Each replay is single-threaded.
while IFS='|' read -r name q event args; do
  selected "$name" "$q" || continue
  in_parallel replay "$name" vision --no-odometry
  if [ "$event" = - ]; then
    in_parallel replay "$name" fused
  else
    in_parallel replay "$name" fused --set daemon.trajectory_poses=online
  fi
done < <(suite)
wait_all

# The table.
table odometry-bench-eval.py || failed=1
echo "renders in $out/renders, runs in $out/runs; replayed with $BIN/ale-slamd $SLAMD_ARGS"
exit $failed
