#!/usr/bin/env bash
# An hour in the same room (issue 33, "hours-long runs in bounded memory"): the loop of the living
# room rendered LAPS times (ale-render --laps: each lap its own sensor noise), then replayed again
# and again for MINUTES minutes of camera time (the frames and the ground truth cycled, timestamps
# going on at 15 fps; the camera alone: a cycled wheel odometry would jump), with the resident set
# sampled once a second (scripts/rss-timeline.sh) and the online poses streamed to a file (final
# poses would keep 0.3 KB a frame in memory for the end of the run).
#
#   scripts/long-run.sh [--minutes M] [--laps L] [--out DIR] render|replay|report|all
#
#   render   DIR/laps (ale-render, 640x480, 15 fps, normal light; about 0.6 s a frame on one core:
#            12 minutes for 3 laps) and DIR/long (links to its frames)
#   replay   ale-slamd --replay DIR/long --lcm-url memq:// (DIR/run.csv frame log, DIR/run.tum
#            online poses, DIR/run.rss.txt, DIR/run.log)
#   report   peak RSS; RSS after minute 10 against the most after it (the issue: flat within 5 %);
#            keyframes and landmarks every 5 minutes; Sim(3) ATE of the first lap, of the last lap
#            and of the whole run, each its own alignment (the issue: the end no worse than the
#            first lap plus 0.1 % of the path)
# Settings (environment): BIN (default build/host/bin), SLAMD_ARGS (extra ale-slamd arguments),
# RENDER_ARGS (extra ale-render arguments, e.g. "--supersample 1" to render faster).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
BIN=${BIN:-$root/build/host/bin}
minutes=60 laps=3 out=/tmp/ale-long-run
die() { echo "long-run.sh: $*" >&2; exit 1; }
while [ $# -gt 1 ]; do
  case $1 in
    --minutes) minutes=$2; shift 2 ;;
    --laps) laps=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) die "unknown option $1" ;;
  esac
done
[ $# -eq 1 ] || die "usage: long-run.sh [--minutes M] [--laps L] [--out DIR] render|replay|report|all"
[[ $minutes =~ ^[0-9]+$ && $minutes -ge 11 ]] || die "--minutes: a whole number >= 11 (the figures start at minute 10)"
[[ $laps =~ ^[0-9]+$ && $laps -ge 1 ]] || die "--laps: a whole number >= 1"
fps=15
frames=$((minutes * 60 * fps))

render() {
  mkdir -p "$out" || die "cannot create $out"
  # shellcheck disable=SC2086
  "$BIN/ale-render" --out "$out/laps" --overwrite --trajectory loop --laps "$laps" --fps $fps --light normal --seed 1 \
    ${RENDER_ARGS:-} > "$out/laps.log" || die "ale-render failed (see $out/laps.log)"
  local names=() poses=() n k ts t0=1700000000000000000
  mapfile -t names < <(grep -v '^#' "$out/laps/mav0/cam0/data.csv" | cut -d, -f2)
  mapfile -t poses < <(grep -v '^#' "$out/laps/groundtruth.txt" | cut -d' ' -f2-)
  n=${#names[@]}
  [ "$n" -gt 0 ] && [ ${#poses[@]} -eq "$n" ] || die "$out/laps: ${n} frames and ${#poses[@]} poses"
  rm -rf "$out/long"
  mkdir -p "$out/long/mav0/cam0/data"
  cp "$out/laps/mav0/cam0/sensor.yaml" "$out/long/mav0/cam0/"
  {
    echo "#timestamp [ns],filename"
    for ((k = 0; k < frames; ++k)); do
      ts=$((t0 + k * 1000000000 / fps))
      ln -s "$out/laps/mav0/cam0/data/${names[k % n]}" "$out/long/mav0/cam0/data/$ts.png"
      echo "$ts,$ts.png"
    done
  } > "$out/long/mav0/cam0/data.csv"
  {
    echo "# timestamp tx ty tz qx qy qz qw"
    for ((k = 0; k < frames; ++k)); do
      ts=$((t0 + k * 1000000000 / fps))
      printf '%d.%09d %s\n' $((ts / 1000000000)) $((ts % 1000000000)) "${poses[k % n]}"
    done
  } > "$out/long/groundtruth.txt"
  echo "long-run: $frames frames ($minutes min) in $out/long, cycling the $n frames of $out/laps ($laps laps)"
}

replay() {
  [ -f "$out/long/mav0/cam0/data.csv" ] || die "nothing rendered in $out/long (run render first)"
  # shellcheck disable=SC2086
  "$root/scripts/rss-timeline.sh" "$out/run.rss.txt" "$out/run.csv" -- \
    /usr/bin/time -v "$BIN/ale-slamd" --replay "$out/long" --lcm-url memq:// --frame-log "$out/run.csv" \
    --trajectory "$out/run.tum" --set daemon.trajectory_poses=online ${SLAMD_ARGS:-} > "$out/run.log" 2>&1 ||
    die "ale-slamd failed (see $out/run.log)"
  echo "long-run: replayed, $(grep -c . "$out/run.csv") frame log lines"
}

# ate GT EST FROM_S TO_S: Sim(3) ATE (cm and % of the path) of the poses in [FROM_S, TO_S).
ate() {
  local gt=$out/ate.gt.tum est=$out/ate.est.tum
  awk -v a="$3" -v b="$4" '!/^#/ && $1 >= a && $1 < b' "$1" > "$gt"
  awk -v a="$3" -v b="$4" '!/^#/ && $1 >= a && $1 < b' "$2" > "$est"
  "$BIN/ale-eval" ate --gt "$gt" --est "$est" --align sim3 --print summary 2>&1 | head -1
}

report() {
  [ -f "$out/run.csv" ] || die "no run in $out (run replay first)"
  echo "long run: $minutes min of camera time, $laps rendered laps cycled; $(grep -o 'frames [0-9]* tracked [0-9]*' "$out/run.log" | tail -1)"
  echo "peak RSS: $(awk '/Maximum resident set size/ {printf "%.1f MB", $NF / 1024}' "$out/run.log")"
  awk -v fps=$fps '{ f = $1; r = $2 / 1024.0
      if (f >= 600 * fps) { if (!at10) at10 = r; if (r > most) most = r } }
    END { if (!at10) { print "rss: the run is shorter than 10 minutes"; exit }
          printf "RSS after minute 10: %.1f MB, the most after it %.1f MB (+%.1f %%)\n", at10, most, 100 * (most - at10) / at10 }' \
    "$out/run.rss.txt"
  awk -F, -v fps=$fps 'NR == 1 { for (i = 1; i <= NF; ++i) { if ($i == "keyframes") k = i; if ($i == "landmarks") l = i }; next }
    (NR - 1) % (300 * fps) == 0 { printf "minute %d: %d keyframes, %d landmarks\n", (NR - 1) / (60 * fps), $k, $l }' "$out/run.csv"
  local t0 lap_s end_s
  t0=$(awk '!/^#/ {print $1; exit}' "$out/long/groundtruth.txt")
  lap_s=$(awk -v n="$laps" '!/^#/ {if (!a) a = $1; b = $1} END {printf "%.3f", (b - a) / n}' "$out/laps/groundtruth.txt")
  end_s=$(awk '!/^#/ {b = $1} END {printf "%.3f", b}' "$out/long/groundtruth.txt")
  add() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.3f", a + b}'; }
  echo "first lap: $(ate "$out/long/groundtruth.txt" "$out/run.tum" "$t0" "$(add "$t0" "$lap_s")")"
  echo "last lap: $(ate "$out/long/groundtruth.txt" "$out/run.tum" "$(add "$end_s" "-$lap_s")" "$(add "$end_s" 1)")"
  echo "whole run: $(ate "$out/long/groundtruth.txt" "$out/run.tum" 0 "$(add "$end_s" 1)")"
}

case $1 in
  render) render ;;
  replay) replay ;;
  report) report ;;
  all) render; replay; report ;;
  *) die "render, replay, report or all" ;;
esac
