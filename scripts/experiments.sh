#!/usr/bin/env bash
# The article's experiments on our firmware (issue 35): renders a suite of sequences, replays each
# with every enhancement.mode (off he clahe gamma ale) and writes docs/results.md
# (scripts/experiments-eval.py: ATE, RPE, tracking, VIA, features, frame time per light condition
# and mode, paired sign tests, the article's Table I beside ours, reports of the five-light loop).
#
#   scripts/experiments.sh [--quick] [--out DIR] [--jobs N] [--results FILE] [--render-only]
#                          [--only NAME]...
#
#   --quick        the five-light loop, one each of off_on, sunlit, dimming and the lanes, two
#                  EuRoC flights and the real TUM frames: within 10 minutes on a 2-core machine
#   --out DIR      renders in DIR/renders (kept: a rerun renders only what is missing or whose
#                  options changed), runs in DIR/runs (a run is redone only when its render, its
#                  ale-slamd arguments or the ale-slamd binary changed); default /tmp/ale-experiments
#   --jobs N       renders and replays at a time (default 2)
#   --results FILE the page to write (default docs/results.md; its plots go to FILE's name
#                  without .md, e.g. docs/results/)
#   --render-only  render the suite and stop
#   --only NAME    just this sequence (may be repeated)
# Settings (environment): BIN (default build/host/bin: ale-render, ale-slamd, ale-eval),
# ALE_DATA_DIR (default ../shared/data: EuRoC ground truth, webcam textures, real frames; what is
# missing is skipped with a message), NICE (default 10: the niceness the whole run takes),
# EUROC_SEEDS (default 1: the EuRoC flights' sensor seeds, e.g. "1 2").
# Every replay is deterministic (mapping inline): each is run once; the first sequence's ale
# replay is run twice and compared (the page says whether they were identical).
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
bench=experiments
out=/tmp/ale-experiments
render_base="--fps 15 --supersample 1"
max_jobs=
results=$root/docs/results.md
args=()
while [ $# -gt 0 ]; do
  case $1 in
    --results) [ $# -ge 2 ] || { echo "experiments: --results needs a file" >&2; exit 2; }; results=$2; shift ;;
    *) args+=("$1") ;;
  esac
  shift
done
# shellcheck source=bench-lib.sh
. "$root/scripts/bench-lib.sh"
parse_bench_args ${args[@]+"${args[@]}"}
case $results in /*) ;; *) results=$PWD/$results ;; esac
data=${ALE_DATA_DIR:-$root/../shared/data}
MODES="off he clahe gamma ale"
renice -n "${NICE:-10}" -p $$ > /dev/null 2>&1 || true

# The light conditions: the five levels of the article's Fig. 10, then the changing ones.
LEVELS="bright normal_bright normal normal_dark dark"
CHANGING="off_on sunlit dimming"

# The EuRoC flights of the article's Table I and the light each is rendered in, like the real
# recordings: the machine halls darker (MH_01, MH_02) and changing (MH_03 dimming), the difficult
# ones dark and switching (MH_04 dark, MH_05 lights off and on), the Vicon rooms normal.
EUROC="MH_01_easy:normal_dark MH_02_easy:normal_dark MH_03_medium:dimming MH_04_difficult:dark
MH_05_difficult:off_on V1_01_easy:normal V1_02_medium:normal V2_01_easy:normal V2_02_medium:normal"

# The rooms of the variants (ale-render options): the living room (6 x 5 m) with two texture
# seeds, three halls, and the webcam photographs as textures (skipped when missing).
rooms() {
  echo "living|"
  echo "living7|--texture-seed 7"
  echo "hall8x6|--room 8x6x2.6 --texture-seed 11"
  echo "hall10x7|--room 10x7x2.8 --texture-seed 23"
  echo "hall7x5|--room 7x5x2.5 --texture-seed 37"
  local cam
  for cam in chamonix courbevoie; do
    [ -d "$data/lighting/webcam/$cam" ] && echo "$cam|--textures $data/lighting/webcam/$cam"
  done
  return 0
}
NOISES=(standard small-pixel fpn vignetting banding jpeg harsh)
ROUTES=("loop|--trajectory loop" "square|--trajectory square --turn-rate 60"
        "lanes|--trajectory lanes --lane-length 2 --lane-width 0.3 --turn-rate 60")
VARIANTS=20   # per light condition (the five-light loop and the EuRoC flights come on top)
# The EuRoC flights' sensor seeds: 640x480 renders cost 10 times a variant's, so one by default.
EUROC_SEEDS=${EUROC_SEEDS:-1}

# The suite, `name|quick|-|ale-render options` (bench-lib.sh): names are GROUP.CONDITION.VARIANT,
# which the evaluator reads. Groups: five (the sweeper loop at the five levels, living room,
# standard noise, seed 1, 20 s), var (VARIANTS per condition: route, room, noise model, sensor
# seed and start spread over the conditions, 12 s), euroc (the nine flights, 640x480, 20 s from
# take-off, per sensor seed in EUROC_SEEDS: seed 1 standard noise, others small-pixel (Vicon rooms)
# or harsh (machine halls) noise).
suite() {
  local level cond i c=0 room_list=() r route noise q
  for level in $LEVELS; do
    q=1
    echo "five.$level.loop|$q|-|--width 320 --height 240 --duration 20 --light $level --seed 1"
  done
  mapfile -t room_list < <(rooms)
  for cond in $LEVELS $CHANGING; do
    c=$((c + 1))
    for ((i = 0; i < VARIANTS; ++i)); do
      r=${room_list[i % ${#room_list[@]}]}
      route=${ROUTES[i % 3]}
      noise=${NOISES[(i + 2 * (i / 7) + c) % 7]}
      q=0
      # --quick: one variant of each changing condition, and the lanes once
      if [ "$i" -eq 0 ] && [[ " $CHANGING " == *" $cond "* ]]; then q=1; fi
      if [ "$i" -eq 2 ] && [ "$cond" = normal ]; then q=1; fi
      echo "var.$cond.${route%%|*}-${r%%|*}-$noise-s$((100 * c + i))|$q|-|--width 320 --height 240 --duration 12" \
           "--light $cond --seed $((100 * c + i)) --start $(((3 * i) % 14)) --noise-model $noise ${route#*|} ${r#*|}"
    done
  done
  if [ -d "$data/euroc_groundtruth" ]; then
    local e seq light s start
    for e in $EUROC; do
      seq=${e%%:*} light=${e#*:}
      [ -f "$data/euroc_groundtruth/$seq.txt" ] || continue
      start=$(takeoff_start "$data/euroc_groundtruth/$seq.txt")
      for s in $EUROC_SEEDS; do
        q=0
        if [ "$s" = 1 ] && { [ "$seq" = V1_01_easy ] || [ "$seq" = MH_04_difficult ]; }; then q=1; fi
        noise=standard
        [ "$s" != 1 ] && noise=$([[ $seq == MH* ]] && echo harsh || echo small-pixel)
        echo "euroc.$light.$seq-$noise-s$s|$q|-|--width 640 --height 480 --duration 20" \
             "--trajectory $data/euroc_groundtruth/$seq.txt --start $start --light $light --seed $s --noise-model $noise"
      done
    done
  fi
}

# The real sequences: `name|quick|dataset|ale-slamd arguments`, replayed where their data is.
# TUM fr2_desk_20: 20 frames with motion (TUM's freiburg2 intrinsics). EuRoC V1_01 micro is left
# out: the vehicle sits still in it, so there is nothing to track or to score.
real_suite() {
  local tum=$data/tum_fr2_desk_20
  [ -d "$tum" ] && echo "real.normal.tum_fr2_desk_20|1|$tum|--set camera.intrinsics.fx=520.9" \
    "--set camera.intrinsics.fy=521.0 --set camera.intrinsics.cx=325.1 --set camera.intrinsics.cy=249.7"
  return 0
}

[ -d "$data/euroc_groundtruth" ] || echo "experiments: $data/euroc_groundtruth is missing: the EuRoC flights are skipped" >&2
[ -d "$data/tum_fr2_desk_20" ] || echo "experiments: $data/tum_fr2_desk_20 is missing: the real sequence is skipped" >&2
[ -d "$data/lighting/webcam" ] || echo "experiments: $data/lighting/webcam is missing: the photo-textured rooms are skipped" >&2

echo "experiments: $(selected_names | wc -l) sequences to render or reuse in $out/renders"
render_suite

# Replays. A run's key (runs/NAME/MODE.key): the ale-slamd binary's checksum, its arguments and
# the render's options; a run whose key is unchanged and that finished is kept.
slamd_sum=$(sha256sum "$BIN/ale-slamd" | cut -d' ' -f1)

# replay NAME DATASET MODE ARGS...: runs/NAME/MODE.{tum,csv,log}.
replay() {
  local name=$1 dataset=$2 mode=$3 dir=$out/runs/$1
  shift 3
  local key
  key="$slamd_sum $* enhancement.mode=$mode $(cat "$dataset/options.txt" 2>/dev/null || echo "$dataset")"
  if [ -f "$dir/$mode.done" ] && [ "$(cat "$dir/$mode.key" 2>/dev/null)" = "$key" ]; then
    return 0
  fi
  mkdir -p "$dir"
  rm -f "$dir/$mode.done"
  if ! "$BIN/ale-slamd" --replay "$dataset" --lcm-url memq:// --no-odometry --trajectory "$dir/$mode.tum" \
       --frame-log "$dir/$mode.csv" --set enhancement.mode="$mode" "$@" > "$dir/$mode.log" 2>&1; then
    echo "replay $name $mode: FAILED (see $dir/$mode.log)" >&2
    return 1
  fi
  echo "$key" > "$dir/$mode.key"
  touch "$dir/$mode.done"
  echo "replay $name $mode: $(grep -Eo 'frames [0-9]+ tracked [0-9]+' "$dir/$mode.log" | tail -1)"
}

# The replays' order: the five-light loop, the EuRoC flights, then the variants by their index
# across the conditions (the first of each condition, the second of each, ...), so that a run cut
# short has about as many sequences of each condition.
mapfile -t names < <(selected_names | awk -F. '{ o = ($1 == "five") ? 0 : ($1 == "euroc") ? 1 : 2; i = 0
  if (match($0, /-s[0-9]+$/)) i = substr($0, RSTART + 2) % 100; print o, i, NR, $0 }' | sort -n -k1,1 -k2,2 -k3,3 |
  cut -d' ' -f4)
reals=()
while IFS='|' read -r name q dataset slamd_args; do
  selected "$name" "$q" && reals+=("$name|$dataset|$slamd_args")
done < <(real_suite)
total=$(((${#names[@]} + ${#reals[@]}) * 5))
k=0
for name in "${names[@]}"; do
  for mode in $MODES; do
    k=$((k + 1))
    [ $((k % 25)) -eq 0 ] && echo "experiments: replay $k of $total"
    in_parallel replay "$name" "$out/renders/$name" "$mode"
  done
done
for item in ${reals[@]+"${reals[@]}"}; do
  IFS='|' read -r name dataset slamd_args <<<"$item"
  for mode in $MODES; do
    # shellcheck disable=SC2086  # the arguments are words
    in_parallel replay "$name" "$dataset" "$mode" $slamd_args
  done
done
wait_all
[ $failed -eq 0 ] || die "a replay failed"

# Determinism: the first sequence's ale replay once more, compared with the kept one.
first=${names[0]}
det=$out/runs/determinism
mkdir -p "$det"
"$BIN/ale-slamd" --replay "$out/renders/$first" --lcm-url memq:// --no-odometry --trajectory "$det/ale.tum" \
  --frame-log "$det/ale.csv" --set enhancement.mode=ale > "$det/ale.log" 2>&1 || die "the second replay of $first failed"
if cmp -s "$det/ale.tum" "$out/runs/$first/ale.tum"; then
  echo "$first ale: the second replay's trajectory is identical to the first's" > "$out/determinism.txt"
else
  echo "$first ale: the second replay's trajectory DIFFERS from the first's" > "$out/determinism.txt"
fi
cat "$out/determinism.txt"

# The page.
cmd="scripts/experiments.sh"
[ "$quick" -eq 1 ] && cmd="$cmd --quick"
for o in ${only[@]+"${only[@]}"}; do cmd="$cmd --only $o"; done
items=("${names[@]}")
for item in ${reals[@]+"${reals[@]}"}; do IFS='|' read -r name dataset _ <<<"$item"; items+=("$name|$dataset"); done
# The build: git describe, `-dirty` when a file other than the page and its plots differs from it.
build=$(git -C "$root" describe --always 2>/dev/null || echo unknown)
rel=${results#"$root"/}
if [ "$build" != unknown ] &&
   [ -n "$(git -C "$root" status --porcelain -- . ":(exclude)$rel" ":(exclude)${rel%.md}")" ]; then
  build=$build-dirty
fi
python3 "$root/scripts/experiments-eval.py" --eval "$BIN/ale-eval" --features "$BIN/ale-features" --data "$data" \
  --out "$out" --results "$results" --command "$cmd" --build "$build" \
  --modes "$MODES" "${items[@]}"
echo "experiments: wrote $results (renders in $out/renders, runs in $out/runs)"
