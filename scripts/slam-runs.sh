#!/usr/bin/env bash
# Rendered SLAM runs behind docs/slam.md's "Current figures":
#
#   scripts/slam-runs.sh euroc render|replay|report     the nine EuRoC flights of the article's
#                                                        Table I, rendered along their ground truth
#   scripts/slam-runs.sh profiles render|replay|report  every ale-render --light profile, sweeper loop
#   scripts/slam-runs.sh long render|replay|report      a 10-minute run (memory: peak RSS)
#
# Each replay runs ale-slamd once per enhancement.mode in MODES (ale and off); ATE by ale-eval, Sim(3).
# Settings (environment): RUNS (output folder, default /tmp/ale-slam-runs), BIN (default
# build/host/bin), EUROC_FPS (15), EUROC_DURATION (40 s; "all" for the rest of the flight),
# EUROC_START (seconds into the file, or auto: 3 s before the body first is 1 m from its start),
# EUROC_SEQS (the nine), PROFILE_SEEDS ("1"), PROFILE_FRAMES (600),
# LONG_FRAMES (9000), JOBS (2: renders or replays at a time), MODES ("ale off": the
# enhancement.mode values replayed, e.g. "ale off clahe he gamma").
# Needs /usr/bin/time for the peak RSS.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
BIN=${BIN:-$root/build/host/bin}
RUNS=${RUNS:-/tmp/ale-slam-runs}
JOBS=${JOBS:-2}
GT_DIR=${GT_DIR:-$root/../shared/data/euroc_groundtruth}
EUROC_FPS=${EUROC_FPS:-15}
EUROC_DURATION=${EUROC_DURATION:-40}
EUROC_START=${EUROC_START:-auto}
EUROC_SEQS=${EUROC_SEQS:-"MH_01_easy MH_02_easy MH_03_medium MH_04_difficult MH_05_difficult V1_01_easy V1_02_medium V2_01_easy V2_02_medium"}
PROFILES=${PROFILES:-"bright normal_bright normal normal_dark dark off_on sunlit dimming"}
PROFILE_SEEDS=${PROFILE_SEEDS:-1}
PROFILE_FRAMES=${PROFILE_FRAMES:-600}
LONG_FRAMES=${LONG_FRAMES:-9000}
MODES=${MODES:-"ale off"}

bench=slam-runs
# shellcheck source=bench-lib.sh
. "$root/scripts/bench-lib.sh"  # die, takeoff_start

# The article's Table I (RMSE ATE, m, real EuRoC): ORB-SLAM3 and ALE-vSLAM.
table1() {
  case $1 in
    MH_01*) echo "0.046894 0.039600" ;; MH_02*) echo "0.035921 0.031765" ;;
    MH_03*) echo "0.045658 0.042196" ;; MH_04*) echo "0.114419 0.060078" ;;
    MH_05*) echo "0.075141 0.055435" ;; V1_01*) echo "0.095272 0.093336" ;;
    V1_02*) echo "0.072214 0.065685" ;; V2_01*) echo "0.085742 0.060736" ;;
    V2_02*) echo "0.084844 0.069165" ;; *) echo "- -" ;;
  esac
}

# Runs the commands read from stdin (one per line), JOBS at a time; fails if any failed.
parallel() {
  local failed=0 pids=() cmd
  while IFS= read -r cmd; do
    bash -c "$cmd" &
    pids+=($!)
    if [ ${#pids[@]} -ge "$JOBS" ]; then
      wait "${pids[0]}" || failed=1
      pids=("${pids[@]:1}")
    fi
  done
  for p in "${pids[@]}"; do wait "$p" || failed=1; done
  return $failed
}

# replay_cmd DIR [sample-rss]: the two replays of DIR, one command line each (summary ->
# DIR/MODE.log); sample-rss: the resident set sampled once a second into DIR/MODE.rss.txt.
replay_cmds() {
  local dir=$1 sample=${2:-} mode wrap=
  for mode in $MODES; do
    [ -n "$sample" ] && wrap="'$root/scripts/rss-timeline.sh' '$dir/$mode.rss.txt' '$dir/$mode.csv' -- "
    echo "$wrap/usr/bin/time -v '$BIN/ale-slamd' --replay '$dir' --trajectory '$dir/$mode.tum' --frame-log '$dir/$mode.csv'" \
         "--set enhancement.mode=$mode --lcm-url memq:// > '$dir/$mode.log' 2>&1 && echo 'replayed $dir $mode'"
  done
}

# ate_of GT EST: Sim(3) ATE RMSE in metres, 4 decimals, or the evaluator's complaint.
ate_of() {
  local out ate
  out=$("$BIN/ale-eval" ate --gt "$1" --est "$2" --align sim3 2>&1 || true)
  ate=$(sed -n 's/^ate_rmse[^0-9]*\([0-9.e+-]*\).*/\1/p' <<<"$out" | head -1)
  if [ -n "$ate" ]; then printf '%.4f' "$ate"; else echo "($(head -1 <<<"$out" | tr ' ' '_'))"; fi
}

# One row: frames, first tracked frame, tracked after it, resets, keyframes, points, ATE (m),
# path (m), peak RSS (MB), median / p95 frame ms.
summarise() {
  local dir=$1 mode=$2
  local log=$dir/$mode.log csv=$dir/$mode.csv
  [ -f "$log" ] || { echo "(no replay)"; return; }
  local summary
  summary=$(grep -E 'frames [0-9]+ tracked' "$log" | tail -1)
  local resets keyframes points med p95 rss
  resets=$(sed -n 's/.* resets \([0-9]*\).*/\1/p' <<<"$summary")
  keyframes=$(sed -n 's/.* keyframes \([0-9]*\).*/\1/p' <<<"$summary")
  points=$(sed -n 's/.* points \([0-9]*\).*/\1/p' <<<"$summary")
  med=$(sed -n 's/.* frame_ms_median \([0-9.]*\).*/\1/p' <<<"$summary")
  p95=$(sed -n 's/.* frame_ms_p95 \([0-9.]*\).*/\1/p' <<<"$summary")
  rss=$(awk '/Maximum resident set size/ {printf "%.1f", $NF / 1024}' "$log")
  # From the frame log: the first tracked frame and the share tracked from there on.
  local share
  share=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "state") c = i; next }
                   { ++n; if (!first && $c == "tracking") first = n; if (first) { ++after; if ($c == "tracking") ++ok } }
                   END { if (first) printf "%d %d/%d %.1f", first - 1, ok, after, 100.0 * ok / after; else printf "never 0/0 0" }' "$csv")
  # ATE, Sim(3): of the whole file when it is one map; after a reset each map has its own frame
  # and scale, so the longest map's, with its share of the poses: "ATE@poses/total" (every file
  # starts with "# map 0").
  local ate path maps
  maps=$(grep -c '^# map' "$dir/$mode.tum" || true)
  if ! grep -qv '^#' "$dir/$mode.tum" 2>/dev/null; then
    ate="-"
  elif [ "$maps" -le 1 ]; then
    ate=$(ate_of "$dir/groundtruth.txt" "$dir/$mode.tum")
  else
    rm -f "$dir/$mode".map*.tum
    awk -v out="$dir/$mode.map" '/^# map/ { ++m; next } /^#/ { next } { print > (out m ".tum") }' "$dir/$mode.tum"
    local longest="" best=0 f n total
    total=$(grep -vc '^#' "$dir/$mode.tum")
    for f in "$dir/$mode".map*.tum; do
      n=$(wc -l < "$f")
      if [ "$n" -gt "$best" ]; then best=$n; longest=$f; fi
    done
    ate="$(ate_of "$dir/groundtruth.txt" "$longest")@$best/$total"
  fi
  path=$(awk '!/^#/ { if (n++) d += sqrt(($2-x)^2 + ($3-y)^2 + ($4-z)^2); x = $2; y = $3; z = $4 } END { printf "%.2f", d }' \
         "$dir/groundtruth.txt")
  echo "$share $resets $keyframes $points $ate $path $rss $med $p95"
}

report_header() {
  echo "| $1 | mode | frames | first tracked | tracked after | % | resets | keyframes | points | ATE (m) | path (m) | peak RSS (MB) | median ms | p95 ms |$2"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|$3"
}

report_dir() {
  local name=$1 dir=$2 extra=${3:-}
  local frames mode
  frames=$(grep -vc '^#' "$dir/mav0/cam0/data.csv")
  for mode in $MODES; do
    read -r first tracked pct resets kf pts ate path rss med p95 <<<"$(summarise "$dir" "$mode")"
    echo "| $name | $mode | $frames | $first | $tracked | $pct | $resets | $kf | $pts | $ate | $path | $rss | $med | $p95 |$extra"
  done
}

euroc() {
  local action=$1 seq
  case $action in
    render)
      for seq in $EUROC_SEQS; do
        local span=(--duration "$EUROC_DURATION") start=$EUROC_START
        [ "$EUROC_DURATION" = all ] && span=()
        [ "$start" = auto ] && start=$(takeoff_start "$GT_DIR/$seq.txt")
        echo "'$BIN/ale-render' --out '$RUNS/euroc/$seq' --overwrite --trajectory '$GT_DIR/$seq.txt'" \
             "--start $start ${span[*]} --fps $EUROC_FPS --light normal --seed 1 > '$RUNS/euroc/$seq.render.log' 2>&1" \
             "&& echo 'rendered $seq from $start s'"
      done | { mkdir -p "$RUNS/euroc"; parallel; } ;;
    replay)
      for seq in $EUROC_SEQS; do replay_cmds "$RUNS/euroc/$seq"; done | parallel ;;
    report)
      report_header sequence " from (s) | Table I ORB-SLAM3 | Table I ALE-vSLAM |" "---|---|---|"
      for seq in $EUROC_SEQS; do
        read -r orb ale <<<"$(table1 "$seq")"
        local start=$EUROC_START
        [ "$start" = auto ] && start=$(takeoff_start "$GT_DIR/$seq.txt")
        report_dir "$seq" "$RUNS/euroc/$seq" " $start | $orb | $ale |"
      done
      for seq in $EUROC_SEQS; do grep -h '^room:' "$RUNS/euroc/$seq.render.log" | sed "s/^/$seq /"; done ;;
    *) die "euroc: render, replay or report" ;;
  esac
}

profiles() {
  local action=$1 p s
  case $action in
    render)
      for s in $PROFILE_SEEDS; do for p in $PROFILES; do
        echo "'$BIN/ale-render' --out '$RUNS/profiles/$p-$s' --overwrite --frames $PROFILE_FRAMES --fps 15" \
             "--light $p --seed $s > '$RUNS/profiles/$p-$s.render.log' 2>&1 && echo 'rendered $p seed $s'"
      done; done | { mkdir -p "$RUNS/profiles"; parallel; } ;;
    replay)
      for s in $PROFILE_SEEDS; do for p in $PROFILES; do replay_cmds "$RUNS/profiles/$p-$s"; done; done | parallel ;;
    report)
      report_header "light (seed)" " mean grey |" "---|"
      for s in $PROFILE_SEEDS; do for p in $PROFILES; do
        local grey
        grey=$(sed -n 's/^mean grey: min \([0-9.]*\), mean \([0-9.]*\), max \([0-9.]*\)/\1 \/ \2 \/ \3/p' \
               "$RUNS/profiles/$p-$s.render.log")
        report_dir "$p ($s)" "$RUNS/profiles/$p-$s" " $grey |"
      done; done ;;
    *) die "profiles: render, replay or report" ;;
  esac
}

# The 10-minute run: one lap of the normal loop (frames 0-396 at 15 fps, 0-26.4 s; a lap is 26.44 s)
# driven again and again: LONG_FRAMES frames whose files link to the lap's, timestamps going on at
# 15 fps, ground truth repeated likewise. The lap is the first 397 frames of the profiles' normal
# seed-1 render when that exists (the same frames: constant light, per-frame noise seeds), else
# rendered here.
long() {
  local action=$1 lap=397 dir=$RUNS/long src=$RUNS/long-lap
  case $action in
    render)
      if [ -f "$RUNS/profiles/normal-1/mav0/cam0/data.csv" ]; then
        src=$RUNS/profiles/normal-1
      else
        mkdir -p "$RUNS" || die "cannot create $RUNS"
        "$BIN/ale-render" --out "$src" --overwrite --frames $lap --fps 15 --light normal --seed 1 > "$src.render.log"
      fi
      rm -rf "$dir"
      mkdir -p "$dir/mav0/cam0/data" "$dir/mav0/state_groundtruth_estimate0"
      cp "$src/mav0/cam0/sensor.yaml" "$dir/mav0/cam0/"
      local names=() poses=()
      mapfile -t names < <(grep -v '^#' "$src/mav0/cam0/data.csv" | cut -d, -f2 | head -$lap)
      mapfile -t poses < <(grep -v '^#' "$src/groundtruth.txt" | cut -d' ' -f2- | head -$lap)
      [ ${#names[@]} -eq $lap ] && [ ${#poses[@]} -eq $lap ] || die "long: $src has ${#names[@]} frames, not $lap"
      local t0=1700000000000000000 k ts
      {
        echo "#timestamp [ns],filename"
        for ((k = 0; k < LONG_FRAMES; ++k)); do
          ts=$((t0 + k * 1000000000 / 15))
          ln -s "$src/mav0/cam0/data/${names[k % lap]}" "$dir/mav0/cam0/data/$ts.png"
          echo "$ts,$ts.png"
        done
      } > "$dir/mav0/cam0/data.csv"
      {
        echo "# timestamp tx ty tz qx qy qz qw"
        for ((k = 0; k < LONG_FRAMES; ++k)); do
          ts=$((t0 + k * 1000000000 / 15))
          printf '%d.%09d %s\n' $((ts / 1000000000)) $((ts % 1000000000)) "${poses[k % lap]}"
        done
      } > "$dir/groundtruth.txt"
      echo "long: $LONG_FRAMES frames in $dir (links to the first $lap frames of $src)" ;;
    replay)
      # the resident set sampled as the run goes (scripts/rss-timeline.sh): flat after minute 1?
      replay_cmds "$dir" sample-rss | parallel ;;
    report)
      report_header run "" ""
      report_dir "10 min, normal loop" "$dir"
      for mode in $MODES; do
        [ -f "$dir/$mode.rss.txt" ] && echo "$mode: $("$root/scripts/rss-timeline.sh" --report "$dir/$mode.rss.txt" 15)"
        [ -f "$dir/$mode.csv" ] && awk -F, -v mode="$mode" 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "keyframes") c = i; next }
          (NR - 1) % 900 == 0 { printf "%s keyframes after minute %d: %s\n", mode, (NR - 1) / 900, $c }' "$dir/$mode.csv"
      done ;;
    *) die "long: render, replay or report" ;;
  esac
}

[ $# -eq 2 ] || die "usage: slam-runs.sh euroc|profiles|long render|replay|report"
for tool in ale-render ale-slamd ale-eval; do [ -x "$BIN/$tool" ] || die "$BIN/$tool is missing (build it)"; done
case $1 in
  euroc) euroc "$2" ;;
  profiles) profiles "$2" ;;
  long) long "$2" ;;
  *) die "unknown group '$1' (euroc, profiles or long)" ;;
esac
