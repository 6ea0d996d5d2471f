#!/usr/bin/env bash
# ale-eval odometry on a rendered square whose odometry is exact (--odometry-noise none):
#   1. at the odometry's own timestamps (30 Hz, every other one a frame's) and interpolated at the
#      frames' timestamps, the camera trajectory it writes matches groundtruth.txt: ATE (SE(3)
#      alignment) under 1e-5 m, and ate --at-time gives the error of one pose;
#   2. a dataset without odometry0/, a sensor.yaml without T_BC and a bad --times are refused with
#      exit 1 / 2 naming the problem.
#   odometry_cli_test.sh ALE_RENDER ALE_EVAL WORK_DIR
set -euo pipefail
render=$1 eval=$2 work=$3
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
seq=$work/exact
"$render" --out "$seq" --trajectory square --turn-rate 90 --duration 10 --fps 15 --width 160 --height 120 \
  --supersample 1 --odometry-noise none --odometry-rate 30 >/dev/null

# below LIMIT VALUE WHAT: VALUE < LIMIT or fail.
below() { awk -v v="$2" -v l="$1" 'BEGIN { exit !(v < l) }' || fail "$3: $2, expected < $1"; }
for times in odometry frames; do
  out=$("$eval" odometry --dataset "$seq" --out "$work/$times.tum" --times "$times")
  echo "$out"
  rows=$(($(wc -l < "$seq/mav0/odometry0/data.csv") - 1))
  frames=$(($(wc -l < "$seq/mav0/cam0/data.csv") - 1))
  if [ "$times" = odometry ]; then
    echo "$out" | grep -qx "poses $rows" || fail "--times odometry: expected $rows poses"
  fi
  figures=$("$eval" ate --gt "$seq/groundtruth.txt" --est "$work/$times.tum" --align se3)
  echo "$figures" | head -3
  # Every frame but the last: ale-render's odometry ends at the last row at or before the last
  # frame's time, which rounding can put one row (33 ms) early.
  pairs=$(echo "$figures" | sed -n 's/^pairs //p')
  [ "$pairs" -ge $((frames - 1)) ] || fail "--times $times: $pairs of $frames frames paired"
  below 1e-5 "$(echo "$figures" | sed -n 's/^ate_rmse //p')" "--times $times: ATE of exact odometry [m]"
done
# One pose's error: the 40th frame's time.
t=$(sed -n '41p' "$seq/groundtruth.txt" | cut -d' ' -f1)
at=$("$eval" ate --gt "$seq/groundtruth.txt" --est "$work/frames.tum" --at-time "$t")
echo "$at" | grep -q "^at_time_s " || fail "--at-time printed no at_time_s"
below 1e-5 "$(echo "$at" | sed -n 's/^at_time_error_m //p')" "--at-time error [m]"
# A time with no pose near it.
set +e
msg=$("$eval" ate --gt "$seq/groundtruth.txt" --est "$work/frames.tum" --at-time 12 2>&1); status=$?
set -e
[ $status = 1 ] && echo "$msg" | grep -q "no pose pair within --max-dt" || fail "--at-time 12: exit $status, '$msg'"

# refused WANT_EXIT PATTERN ARGS...: ale-eval ARGS must exit WANT_EXIT naming PATTERN.
refused() {
  local want=$1 pattern=$2 status msg
  shift 2
  set +e
  msg=$("$eval" "$@" 2>&1)
  status=$?
  set -e
  echo "$msg" | head -1
  [ "$status" = "$want" ] || fail "$*: exit $status, expected $want"
  echo "$msg" | grep -qF -- "$pattern" || fail "$*: '$pattern' not said"
}
refused 2 "--times must be odometry or frames" odometry --dataset "$seq" --out "$work/x.tum" --times gt
refused 2 "missing --dataset DIR" odometry --out "$work/x.tum"
cp -r "$seq" "$work/no_tbc"
sed -i '/^T_BC:/,/data:/d' "$work/no_tbc/mav0/odometry0/sensor.yaml"
grep -q T_BC "$work/no_tbc/mav0/odometry0/sensor.yaml" && fail "T_BC not removed from the copy"
refused 1 "sensor.yaml: no T_BC" odometry --dataset "$work/no_tbc" --out "$work/x.tum"
cp -r "$seq" "$work/no_odometry"
rm -r "$work/no_odometry/mav0/odometry0"
refused 1 "no wheel odometry (mav0/odometry0/data.csv)" odometry --dataset "$work/no_odometry" --out "$work/x.tum"
echo "odometry_cli_test: ok"
