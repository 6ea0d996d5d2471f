#!/usr/bin/env bash
# End to end: render a short sweeper sequence, replay it through ale-slamd into an LCM log file
# (file://LOG?mode=w: no network), then decode the log with LCM's Java reader and the Java classes
# lcm-gen made from app/lcm (AleLcmLogCheck), checking the first and last pose and status
# against the frame log and the dataset's timestamps.
#   lcm_log_e2e.sh WORKDIR ALE_RENDER ALE_SLAMD CLASSPATH [EMULATOR...]
set -euo pipefail
work=$1 render=$2 slamd=$3 classpath=$4
shift 4
emulator=("$@")  # qemu-arm for the armhf daemon; empty on the host
rm -rf "$work"
mkdir -p "$work"
"${emulator[@]}" "$render" --out "$work/seq" --frames 24 --fps 15 --width 160 --height 120 --supersample 1 \
  --light off_on >"$work/render.txt"
"${emulator[@]}" "$slamd" --replay "$work/seq" --lcm-url "file://$work/daemon.lcmlog?mode=w" \
  --frame-log "$work/frames.csv"
java -cp "$classpath" AleLcmLogCheck "$work/daemon.lcmlog" "$work/frames.csv" "$work/seq/mav0/cam0/data.csv"
