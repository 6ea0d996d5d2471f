#!/usr/bin/env bash
# A calibration made by ale-calibrate tracks as well as the true one: a sweeper loop rendered
# through a distorted lens (ale-render --lens radtan, or fisheye) is replayed by ale-slamd once with the
# sequence's own sensor.yaml (the true lens) and once with the lens ale-calibrate fitted to
# checkerboard views rendered through the same lens (camera.calibration_file); the ATE (Sim(3),
# ale-eval) with the fitted lens must be within 10 % of the true lens's or below it. A control
# replay with the fitted lens's distortion zeroed must do far worse (more than twice the ATE),
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
"$render" --out "$work/seq" --frames "$frames" --fps 15 --lens "$lens" --seed 1 --supersample 2 >"$work/render.log"
"$render" --checkerboard 9x6 --square 0.03 --lens "$lens" --views 30 --seed 2 --out "$work/views" >/dev/null
"$calibrate" --board 9x6 --square 0.03 --model "$model" --extrinsics "$work/seq/mav0/cam0/sensor.yaml" --out "$work/fitted.yaml" \
  "$work/views" >"$work/calibrate.log" || { cat "$work/calibrate.log"; fail "ale-calibrate exited with $?"; }
sed 's/^distortion_coefficients: .*/distortion_coefficients: [0, 0, 0, 0]/' "$work/fitted.yaml" >"$work/no_distortion.yaml"

# replay NAME [--set camera.calibration_file=FILE]: prints the ATE RMSE in metres.
replay() {
  local name=$1; shift
  "$slamd" --replay "$work/seq" --lcm-url memq:// --no-odometry --trajectory "$work/$name.tum" "$@" 2>"$work/$name.log" ||
    { cat "$work/$name.log" >&2; fail "the $name replay exited with $?"; }
  "$eval" ate --gt "$work/seq/groundtruth.txt" --est "$work/$name.tum" --align sim3 >"$work/$name.ate" ||
    { cat "$work/$name.ate" >&2; fail "ale-eval on the $name replay failed"; }
  awk '$1 == "ate_rmse" {print $2}' "$work/$name.ate"
}
true_ate=$(replay true)
fitted_ate=$(replay fitted --set camera.calibration_file="$work/fitted.yaml")
control_ate=$(replay no_distortion --set camera.calibration_file="$work/no_distortion.yaml")
grep -E "^(rms|fx|fy|cx|cy|k1|k2|k3|k4|p1|p2) " "$work/calibrate.log"
grep -h "tracked" "$work/true.log" "$work/fitted.log" "$work/no_distortion.log" | sed 's/.*ale-slamd: //'
awk -v t="$true_ate" -v f="$fitted_ate" -v c="$control_ate" 'BEGIN {
  printf "calibrated_replay: ATE %.2f cm with the true lens, %.2f cm with ale-calibrate'"'"'s (%+.0f %%), %.2f cm without distortion\n",
         100 * t, 100 * f, 100 * (f - t) / t, 100 * c
  exit !(f <= 1.10 * t && c > 2 * t)
}' || fail "the fitted lens's ATE is not within 10 % of the true lens's, or the control is not worse"
echo "calibrated_replay_e2e: ok"
