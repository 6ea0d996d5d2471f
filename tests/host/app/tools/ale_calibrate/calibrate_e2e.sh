#!/usr/bin/env bash
# ale-calibrate end to end on checkerboard views ale-render makes through a known lens:
#   1. a folder of views with one copied twice: the copy is rejected as a duplicate, the lens is
#      written (exit 0) and loads through the daemon's own sensor.yaml reader (ale-render
#      --camera uses it: hal/replay read_euroc_sensor_yaml);
#   2. the same views as a recording of the daemon's recorder (EuRoC layout) calibrate the same;
#   3. --max-blur below any edge: every view rejected as blurred, "too few good views" (exit 1);
#   4. a board size that is not the one shown: "no board found" (exit 1);
#   5. fewer views than --min-views: "too few good views" (exit 1);
#   6. a fisheye lens calibrates with --model fisheye;
#   7. one view through another lens among the views: rejected as a poor fit, the rest refitted.
#
#   calibrate_e2e.sh WORK_DIR ALE_CALIBRATE ALE_RENDER
set -euo pipefail
work=$1 calibrate=$2 render=$3
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
# expect EXIT PATTERN COMMAND...: the command's exit status and a line of its output.
expect() {
  local want=$1 pattern=$2; shift 2
  local got=0
  "$@" >"$work/out.txt" 2>&1 || got=$?
  cat "$work/out.txt"
  [ "$got" = "$want" ] || fail "$* exited with $got, not $want"
  grep -Eq "$pattern" "$work/out.txt" || fail "$* did not print /$pattern/"
}

"$render" --checkerboard 9x6 --square 0.03 --lens radtan --views 10 --supersample 2 --seed 5 --out "$work/views" >/dev/null
cp "$work/views/view_003.png" "$work/views/view_003_again.png"
board=(--board 9x6 --square 0.03)

# 1.
expect 0 "10 views used of 11 images" "$calibrate" "${board[@]}" --out "$work/cal.yaml" "$work/views"
grep -Eq "rejected .*view_003_again.png: duplicate of view_003.png" "$work/out.txt" || fail "no duplicate rejected"
grep -Eq "^rms 0\.[0-2][0-9]* px" "$work/out.txt" || fail "rms not under 0.3 px"
[ -s "$work/cal.html" ] || fail "no report beside the calibration"
grep -q "<svg" "$work/cal.html" || fail "the report has no pictures"
grep -q "distortion_model: radial-tangential" "$work/cal.yaml" || fail "no radtan model in the file"
expect 0 "1 checkerboard views" "$render" --camera "$work/cal.yaml" --checkerboard 9x6 --views 1 --supersample 1 --out "$work/reload"

# 2.
rec=$work/rec/000001_20260101T000000Z/mav0/cam0
mkdir -p "$rec/data"
echo "#timestamp [ns],filename" >"$rec/data.csv"
t=1000000000
for f in "$work"/views/view_0??.png; do
  cp "$f" "$rec/data/$t.png"
  echo "$t,$t.png" >>"$rec/data.csv"
  t=$((t + 100000000))
done
expect 0 "10 views used of 10 images" "$calibrate" "${board[@]}" --out "$work/rec.yaml" "$work/rec"
grep -v '^#\|^comment' "$work/cal.yaml" >"$work/a.txt"
grep -v '^#\|^comment' "$work/rec.yaml" >"$work/b.txt"
cmp -s "$work/a.txt" "$work/b.txt" || fail "the recording's calibration differs from the folder's"

# 3 to 5.
expect 1 "too few good views: 0 of 11 images.*11 blurred" "$calibrate" "${board[@]}" --max-blur 0.5 --out "$work/x.yaml" "$work/views"
# (two images: OpenCV's detector searches long for a wrong-sized board in a real one)
expect 1 "no board found: none of the 2 images shows all 7x5 inner corners" "$calibrate" --board 7x5 --square 0.03 \
  --out "$work/x.yaml" "$work"/views/view_000.png "$work"/views/view_001.png
expect 1 "too few good views: 3 of 3 images, at least 8 needed" "$calibrate" "${board[@]}" --out "$work/x.yaml" \
  "$work"/views/view_000.png "$work"/views/view_001.png "$work"/views/view_002.png

# 6.
"$render" --checkerboard 9x6 --square 0.03 --lens fisheye --views 10 --supersample 2 --seed 6 --out "$work/fisheye" >/dev/null
expect 0 "10 views used of 10 images.*model fisheye" "$calibrate" "${board[@]}" --model fisheye --out "$work/fisheye.yaml" "$work/fisheye"
grep -q "distortion_model: equidistant" "$work/fisheye.yaml" || fail "no equidistant model in the file"
# 7.
sed 's/^distortion_coefficients: .*/distortion_coefficients: [-0.1, 0.0, 0.0, 0.0]/; s/^intrinsics: .*/intrinsics: [300, 300, 300, 250]/' \
  "$work/views/calibration.yaml" >"$work/other_lens.yaml"
"$render" --camera "$work/other_lens.yaml" --checkerboard 9x6 --views 1 --seed 9 --supersample 2 --out "$work/other" >/dev/null
mkdir -p "$work/mixed"
cp "$work"/views/view_0??.png "$work/mixed/"
cp "$work/other/view_000.png" "$work/mixed/view_other_lens.png"
expect 0 "10 views used of 11 images" "$calibrate" "${board[@]}" --out "$work/mixed.yaml" "$work/mixed"
grep -Eq "rejected .*view_other_lens.png: poor fit: RMS [0-9.]+ px" "$work/out.txt" || fail "the other lens's view was not rejected"
echo "calibrate_e2e: ok"
