#!/usr/bin/env bash
# A calibration made by ale-calibrate tracks as well as the true one: a sweeper loop rendered
# through a distorted lens (ale-render --lens radtan, or fisheye) is replayed by ale-slamd once with the
# sequence's own sensor.yaml (the true lens) and once with the lens ale-calibrate fitted to
# checkerboard views rendered through the same lens (camera.calibration_file). One loop's ATE
# swings by 2x when the true lens's fx moves by a hundredth of a pixel (docs/calibration.md), so
# the comparison is over three loops (sensor seeds 1-3): the mean ATE (Sim(3), ale-eval) with
# the fitted lens must be within 10 % of the true lens's or below it. A control replay with the
# fitted lens's distortion zeroed must do far worse (a mean more than twice the true lens's),
# which shows the comparison can tell lenses apart. The replays run on vision alone
# (--no-odometry): the lens is what is compared, and the render's wheel odometry would carry the
# trajectory past a poor one.
#
#   calibrated_replay_e2e.sh WORK_DIR ALE_RENDER ALE_CALIBRATE ALE_SLAMD ALE_EVAL [FRAMES [LENS]]
# LENS: radtan (default) or fisheye (calibrated with --model fisheye).
set -euo pipefail
work=$1 render=$2 calibrate=$3 slamd=$4 eval=$5 frames=${6:-300} lens=${7:-radtan}
model=pinhole
[ "$lens" = fisheye ] && model=fisheye
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
"$render" --checkerboard 9x6 --square 0.03 --lens "$lens" --views 30 --seed 2 --out "$work/views" >/dev/null
seeds="1 2 3"
for seed in $seeds; do
  "$render" --out "$work/seq$seed" --frames "$frames" --fps 15 --lens "$lens" --seed "$seed" --supersample 2 >"$work/render$seed.log"
done
"$calibrate" --board 9x6 --square 0.03 --model "$model" --extrinsics "$work/seq1/mav0/cam0/sensor.yaml" --out "$work/fitted.yaml" \
  "$work/views" >"$work/calibrate.log" || { cat "$work/calibrate.log"; fail "ale-calibrate exited with $?"; }
sed 's/^distortion_coefficients: .*/distortion_coefficients: [0, 0, 0, 0]/' "$work/fitted.yaml" >"$work/no_distortion.yaml"

# replay SEED NAME [--set camera.calibration_file=FILE]: prints the ATE RMSE in metres.
replay() {
  local seed=$1 name=$2; shift 2
  "$slamd" --replay "$work/seq$seed" --lcm-url memq:// --no-odometry --trajectory "$work/$name$seed.tum" "$@" 2>"$work/$name$seed.log" ||
    { cat "$work/$name$seed.log" >&2; fail "the $name replay of seed $seed exited with $?"; }
  "$eval" ate --gt "$work/seq$seed/groundtruth.txt" --est "$work/$name$seed.tum" --align sim3 >"$work/$name$seed.ate" ||
    { cat "$work/$name$seed.ate" >&2; fail "ale-eval on the $name replay of seed $seed failed"; }
  awk '$1 == "ate_rmse" {print $2}' "$work/$name$seed.ate"
}
grep -E "^(rms|fx|fy|cx|cy|k1|k2|k3|k4|p1|p2) " "$work/calibrate.log"
true_sum=0 fitted_sum=0 control_sum=0
for seed in $seeds; do
  t=$(replay "$seed" true)
  f=$(replay "$seed" fitted --set camera.calibration_file="$work/fitted.yaml")
  c=$(replay "$seed" no_distortion --set camera.calibration_file="$work/no_distortion.yaml")
  grep -h "tracked" "$work/true$seed.log" "$work/fitted$seed.log" "$work/no_distortion$seed.log" | sed "s/.*ale-slamd: /seed $seed: /"
  awk -v s="$seed" -v t="$t" -v f="$f" -v c="$c" 'BEGIN { printf "seed %s: ATE %.2f cm true lens, %.2f cm ale-calibrate'"'"'s, %.2f cm without distortion\n", s, 100 * t, 100 * f, 100 * c }'
  true_sum=$(awk -v a="$true_sum" -v b="$t" 'BEGIN { print a + b }')
  fitted_sum=$(awk -v a="$fitted_sum" -v b="$f" 'BEGIN { print a + b }')
  control_sum=$(awk -v a="$control_sum" -v b="$c" 'BEGIN { print a + b }')
done
awk -v t="$true_sum" -v f="$fitted_sum" -v c="$control_sum" 'BEGIN {
  printf "calibrated_replay: mean ATE %.2f cm with the true lens, %.2f cm with ale-calibrate'"'"'s (%+.0f %%), %.2f cm without distortion\n",
         100 * t / 3, 100 * f / 3, 100 * (f - t) / t, 100 * c / 3
  exit !(f <= 1.10 * t && c > 2 * t)
}' || fail "the fitted lens's mean ATE is not within 10 % of the true lens's, or the control is not worse"
echo "calibrated_replay_e2e: ok"
