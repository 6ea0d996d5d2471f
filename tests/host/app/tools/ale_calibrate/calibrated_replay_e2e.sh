#!/usr/bin/env bash
# A calibration made by ale-calibrate tracks as well as the true one: sweeper loops rendered
# through a distorted lens (ale-render --lens radtan, or fisheye) are replayed by ale-slamd with
# the sequences' own sensor.yaml (the true lens) and with the lens ale-calibrate fitted to
# checkerboard views rendered through the same lens (camera.calibration_file).
#
# One replay's ATE is chaotic: a lens changed by a hundredth of a pixel, or the replay started a
# frame later, moves it by 10 to 60 % and now and then by 2x to 5x (docs/calibration.md,
# Replays). So the comparison is over many replays, in pairs: every rendered loop (sensor seeds
# SEEDS) replayed from each of the first frames in OFFSETS (the frames before it left out of the
# replay's frame list), once with each lens. The mean ATE (Sim(3), ale-eval) with the fitted lens
# must be within 10 % of the true lens's or below it; the standard error of the pairs' mean
# difference is printed beside it. A control replay of each loop (from the first of OFFSETS) with
# the fitted lens's distortion zeroed must do far worse (a mean more than twice the true lens's
# on the same replays), which shows the comparison can tell lenses apart. The replays run on
# vision alone (--no-odometry): the lens is what is compared, and the render's wheel odometry
# would carry the trajectory past a poor one.
#
#   calibrated_replay_e2e.sh WORK_DIR ALE_RENDER ALE_CALIBRATE ALE_SLAMD ALE_EVAL [FRAMES [LENS]]
# LENS: radtan (default) or fisheye (calibrated with --model fisheye). SEEDS and OFFSETS may be
# set in the environment (defaults below).
set -euo pipefail
work=$1 render=$2 calibrate=$3 slamd=$4 eval=$5 frames=${6:-300} lens=${7:-radtan}
seeds=${SEEDS:-"1 2"}
offsets=${OFFSETS:-"0 1 2 3 4 5 7 9 11 14 18 22"}
model=pinhole
[ "$lens" = fisheye ] && model=fisheye
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
"$render" --checkerboard 9x6 --square 0.03 --lens "$lens" --views 30 --seed 2 --out "$work/views" >/dev/null
for seed in $seeds; do
  "$render" --out "$work/seq$seed" --frames "$frames" --fps 15 --lens "$lens" --seed "$seed" --supersample 2 >"$work/render$seed.log"
done
"$calibrate" --board 9x6 --square 0.03 --model "$model" --extrinsics "$work/seq${seeds%% *}/mav0/cam0/sensor.yaml" \
  --out "$work/fitted.yaml" "$work/views" >"$work/calibrate.log" || { cat "$work/calibrate.log"; fail "ale-calibrate exited with $?"; }
sed 's/^distortion_coefficients: .*/distortion_coefficients: [0, 0, 0, 0]/' "$work/fitted.yaml" >"$work/no_distortion.yaml"

# start SEED OFFSET: prints a dataset that replays loop SEED from its frame OFFSET on (its images,
# ground truth and lens shared with the loop, only the frame list shortened).
start() {
  local seed=$1 offset=$2
  [ "$offset" = 0 ] && { echo "$work/seq$seed"; return; }
  local src=$work/seq$seed dst=$work/seq$seed.from$offset
  mkdir -p "$dst/mav0/cam0"
  ln -sfn "$src/groundtruth.txt" "$dst/groundtruth.txt"
  ln -sfn "$src/mav0/cam0/data" "$dst/mav0/cam0/data"
  cp "$src/mav0/cam0/sensor.yaml" "$dst/mav0/cam0/sensor.yaml"
  { head -n 1 "$src/mav0/cam0/data.csv"; tail -n +"$((offset + 2))" "$src/mav0/cam0/data.csv"; } >"$dst/mav0/cam0/data.csv"
  echo "$dst"
}
# replay DATASET NAME [--set camera.calibration_file=FILE]: prints the ATE RMSE in metres.
replay() {
  local data=$1 name=$2; shift 2
  "$slamd" --replay "$data" --lcm-url memq:// --no-odometry --trajectory "$work/$name.tum" "$@" 2>"$work/$name.log" ||
    { cat "$work/$name.log" >&2; fail "the $name replay exited with $?"; }
  "$eval" ate --gt "$data/groundtruth.txt" --est "$work/$name.tum" --align sim3 >"$work/$name.ate" ||
    { cat "$work/$name.ate" >&2; fail "ale-eval on the $name replay failed"; }
  awk '$1 == "ate_rmse" {print $2}' "$work/$name.ate"
}
grep -E "^(rms|fx|fy|cx|cy|k1|k2|k3|k4|p1|p2) " "$work/calibrate.log"
: >"$work/pairs.txt"
: >"$work/controls.txt"
for seed in $seeds; do
  for offset in $offsets; do
    data=$(start "$seed" "$offset")
    t=$(replay "$data" "true$seed.$offset")
    f=$(replay "$data" "fitted$seed.$offset" --set camera.calibration_file="$work/fitted.yaml")
    echo "$t $f" >>"$work/pairs.txt"
    awk -v s="$seed" -v o="$offset" -v t="$t" -v f="$f" \
      'BEGIN { printf "seed %s from frame %s: ATE %.2f cm true lens, %.2f cm ale-calibrate'"'"'s\n", s, o, 100 * t, 100 * f }'
  done
  first=${offsets%% *}
  c=$(replay "$(start "$seed" "$first")" "no_distortion$seed" --set camera.calibration_file="$work/no_distortion.yaml")
  t=$(awk '$1 == "ate_rmse" {print $2}' "$work/true$seed.$first.ate")
  echo "$t $c" >>"$work/controls.txt"
  grep -h "tracked" "$work/true$seed.$first.log" "$work/fitted$seed.$first.log" "$work/no_distortion$seed.log" |
    sed "s/.*ale-slamd: /seed $seed: /"
done
awk 'FNR == NR { n++; t += $1; f += $2; d[n] = $2 - $1; next } { ct += $1; cc += $2; m++ }
  END {
    md = (f - t) / n; for (i = 1; i <= n; i++) ss += (d[i] - md) ^ 2
    se = sqrt(ss / (n - 1) / n)
    printf "calibrated_replay: mean ATE over %d replays %.3f cm with the true lens, %.3f cm with ale-calibrate'"'"'s (%+.1f %%, standard error %.1f %%); without distortion %.2f cm against %.2f cm over %d\n",
           n, 100 * t / n, 100 * f / n, 100 * (f - t) / t, 100 * se * n / t, 100 * cc / m, 100 * ct / m, m
    exit !(f <= 1.10 * t && cc > 2 * ct)
  }' "$work/pairs.txt" "$work/controls.txt" ||
  fail "the fitted lens's mean ATE is not within 10 % of the true lens's, or the control is not worse"
echo "calibrated_replay_e2e: ok"
