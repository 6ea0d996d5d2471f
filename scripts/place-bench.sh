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
BIN=${BIN:-$root/build/host/bin}
SLAMD_ARGS=${SLAMD_ARGS:-}
out=/tmp/ale-place-bench
jobs=2
quick=0
render_only=0
only=()

die() { echo "place-bench: $*" >&2; exit 2; }

while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=1 ;;
    --out) [ $# -ge 2 ] || die "--out needs a folder"; out=$2; shift ;;
    --jobs) [ $# -ge 2 ] && [[ $2 =~ ^[1-9][0-9]*$ ]] || die "--jobs needs a whole number >= 1"; jobs=$2; shift ;;
    --render-only) render_only=1 ;;
    --only) [ $# -ge 2 ] || die "--only needs a sequence name"; only+=("$2"); shift ;;
    -h|--help) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown option '$1' (see --help)" ;;
  esac
  shift
done
for tool in ale-render ale-slamd ale-eval; do
  [ -x "$BIN/$tool" ] || die "$BIN/$tool is missing: build it (ninja -C build/host $tool)"
done
command -v python3 >/dev/null || die "python3 is needed for the table"

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

selected() {
  local name=$1 q=$2 o
  if [ ${#only[@]} -gt 0 ]; then
    for o in "${only[@]}"; do [ "$o" = "$name" ] && return 0; done
    return 1
  fi
  [ $quick -eq 0 ] || [ "$q" = 1 ]
}

render_args() {  # event options: the event's ale-render flag and value
  local event=$1
  case $event in
    blackout:*) echo "--blackout ${event#blackout:}" ;;
    kidnap:*) echo "--kidnap ${event#kidnap:}" ;;
    *) echo "" ;;
  esac
}

mkdir -p "$out/renders" "$out/runs"
names=()
while IFS='|' read -r name q event args; do
  selected "$name" "$q" || continue
  names+=("$name")
done < <(suite)
[ ${#names[@]} -gt 0 ] || die "no sequence selected (names: $(suite | cut -d'|' -f1 | tr '\n' ' '))"

# Renders: DIR/renders/NAME, with the options it was made with in NAME/options.txt; a folder whose
# options differ (or that never finished) is rendered again.
render_one() {
  local name=$1 options=$2 dir=$out/renders/$1
  if [ -f "$dir/options.txt" ] && [ "$(cat "$dir/options.txt")" = "$options" ]; then
    echo "render $name: cached"
    return 0
  fi
  rm -rf "$dir" "$dir.part"
  # shellcheck disable=SC2086  # the options are words
  if ! "$BIN/ale-render" --out "$dir.part" --fps 15 --width 640 --height 480 --seed 1 $options > "$dir.part.log" 2>&1; then
    echo "render $name: FAILED (see $dir.part.log)" >&2
    return 1
  fi
  mv "$dir.part.log" "$dir.part/render.log"
  echo "$options" > "$dir.part/options.txt"
  mv "$dir.part" "$dir"
  echo "render $name: $(grep -E '^time:' "$dir/render.log")"
}

pids=()
failed=0
while IFS='|' read -r name q event args; do
  selected "$name" "$q" || continue
  render_one "$name" "$args $(render_args "$event")" &
  pids+=($!)
  if [ ${#pids[@]} -ge "$jobs" ]; then
    wait "${pids[0]}" || failed=1
    pids=("${pids[@]:1}")
  fi
done < <(suite)
for p in "${pids[@]}"; do wait "$p" || failed=1; done
[ $failed -eq 0 ] || die "a render failed"
[ $render_only -eq 0 ] || exit 0

# Replays, one at a time (each is single-threaded and deterministic).
for name in "${names[@]}"; do
  run=$out/runs/$name
  # shellcheck disable=SC2086  # SLAMD_ARGS are words
  if ! "$BIN/ale-slamd" --replay "$out/renders/$name" --lcm-url memq:// --trajectory "$run.tum" \
       --frame-log "$run.frames.csv" $SLAMD_ARGS > "$run.log" 2>&1; then
    echo "replay $name: FAILED (see $run.log)" >&2
    failed=1
  fi
done

# The table.
rows=()
while IFS='|' read -r name q event args; do
  selected "$name" "$q" || continue
  rows+=("$name|$event")
done < <(suite)
python3 "$root/scripts/place-bench-eval.py" --eval "$BIN/ale-eval" --renders "$out/renders" --runs "$out/runs" \
  "${rows[@]}"
echo "renders in $out/renders, runs in $out/runs; replayed with $BIN/ale-slamd $SLAMD_ARGS"
exit $failed
