#!/usr/bin/env bash
# ale-slamd as a process: SIGHUP reloads the file (runtime keys taken over, an enhancement
# threshold among them; a restart key kept; a bad file refused while the daemon runs on), SIGTERM
# stops it cleanly (exit 0).
#   signals_e2e.sh WORKDIR ALE_SLAMD DATASET
set -euo pipefail
work=$1 slamd=$2 dataset=$3
rm -rf "$work"
mkdir -p "$work"
conf=$work/ale.conf
log=$work/daemon.txt
printf '[log]\nlevel = info\n' >"$conf"
"$slamd" --config "$conf" --replay "$dataset" --lcm-url memq:// >"$log" 2>&1 &
pid=$!
# Waits (up to 10 s) for a line of the daemon's output.
wait_for() {
  for _ in $(seq 100); do
    grep -q "$1" "$log" && return 0
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  echo "signals_e2e: no '$1' in the daemon's output:" >&2
  cat "$log" >&2
  kill "$pid" 2>/dev/null || true
  exit 1
}
wait_for "first status published"
printf '[gpio]\nir_on_dark_frames = 2\n[camera]\nwidth = 320\n[features.enhance.grading]\nt_low = 75\n' >"$conf"
kill -HUP "$pid"
wait_for "configuration generation 1: gpio.ir_on_dark_frames = 2, features.enhance.grading.t_low = 75"
printf '[gpio]\nir_on_dark_frames = 0\n' >"$conf"
kill -HUP "$pid"
wait_for "configuration reload refused, generation 1 kept"
kill -TERM "$pid"
status=0
wait "$pid" || status=$?
cat "$log"
[ "$status" = 0 ] || { echo "signals_e2e: exit status $status after SIGTERM" >&2; exit 1; }
