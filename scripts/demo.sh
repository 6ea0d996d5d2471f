#!/usr/bin/env bash
# The main job on a default input that needs nothing but the repository: render a short sweeper
# sequence in which the lights go off and on again, replay it through ale-slamd (the whole
# pipeline: lighting-adaptive front end, tracking, inline mapping), print the trajectory's ATE
# against the rendered ground truth, extract features on a dark frame with the baseline and the
# ALE detector, and write a report with the top view of estimate and ground truth and the
# per-frame plots. Ends with a short summary (ATE in cm and % of the path, share of frames
# tracked, frame time) and where the report is; the report opens with the same lines.
#
#   scripts/demo.sh [OUT_DIR]        (default build/demo; the rendered sequence is cached there)
#
# Installs what is missing and builds only the five tools it runs first (scripts/build.sh host
# Release TOOLS...; the tests and benchmarks are left to scripts/test.sh).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$root/build/demo}
bin=$root/build/host/bin
mkdir -p "$out"

tools=(ale-slamd ale-render ale-enhance ale-features ale-eval)
start=$(date +%s)
echo "== dependencies (first run: Debian packages and OpenCV, a few minutes; log in $out/setup.log)"
# setup-deps' own lines live (what it installs and changes, a wait for another apt), apt's in the log
if ! "$root/scripts/setup-deps.sh" host >"$out/setup.log" 2> >(tee -a "$out/setup.log" | grep --line-buffered '^setup-deps:' >&2); then
  sleep 1; tail -30 "$out/setup.log"; exit 1
fi
echo "== building ${tools[*]} (log in $out/build.log)"
"$root/scripts/build.sh" host Release "${tools[@]}" >"$out/build.log" 2>&1 || { tail -30 "$out/build.log"; exit 1; }
echo "   dependencies and build: $(( $(date +%s) - start )) s"

seq=$out/sweeper_off_on
if [ ! -f "$seq/mav0/cam0/data.csv" ]; then
  echo "== rendering 10 s of a sweeper driving a loop; lights off at 3 s, on at 6 s"
  "$bin/ale-render" --out "$seq" --frames 300 --fps 30 --light off_on --trajectory loop --seed 1 --overwrite
else
  echo "== using the rendered sequence in $seq"
fi

echo "== replaying it through ale-slamd (in-process LCM)"
"$bin/ale-slamd" --replay "$seq" --lcm-url memq:// --frame-log "$out/frames.csv" --trajectory "$out/trajectory.tum"

# A frame from the dark middle of the sequence and one from the lit start.
dark=$(sed -n '2~1p' "$seq/mav0/cam0/data.csv" | sed -n '135p' | cut -d, -f2 | tr -d ' \r')
lit=$(sed -n '2~1p' "$seq/mav0/cam0/data.csv" | sed -n '30p' | cut -d, -f2 | tr -d ' \r')
echo "== enhancement of a lit and a dark frame (before/after images in $out/enhance)"
"$bin/ale-enhance" --out "$out/enhance" "$seq/mav0/cam0/data/$lit" "$seq/mav0/cam0/data/$dark"

echo "== features on the dark frame: baseline (ORB-SLAM3-like) vs ALE (overlays in $out/features)"
"$bin/ale-features" --mode all --out "$out/features" "$seq/mav0/cam0/data/$dark"

echo "== trajectory against the ground truth (Sim(3) alignment: monocular scale), per-frame figures, report"
echo
if ! "$bin/ale-eval" ate --gt "$seq/groundtruth.txt" --est "$out/trajectory.tum" --align sim3 \
  --frame-log "$out/frames.csv" --report "$out/report.html" --print summary; then
  echo "(no trajectory to evaluate: the report shows the per-frame figures only)"
  "$bin/ale-eval" report --frame-log "$out/frames.csv" --out "$out/report.html" --print summary
fi
