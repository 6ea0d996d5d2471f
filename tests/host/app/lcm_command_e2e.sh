#!/usr/bin/env bash
# Commands over LCM to a running ale-slamd in another process: LCM's Java TCPService is the hub
# of the tcpq:// provider (plain TCP on 127.0.0.1: no multicast, unlike udpm://, and two-way,
# unlike file://), the daemon replays a short rendered sequence on it, and AleLcmCommandCheck (a
# controller written against LCM's Java classes and lcm-gen's) sends SAVE_MAP to a file in WORKDIR,
# RESET_MAP and an unknown command once the map has keyframes, then LOAD_MAP of a file that is not
# a map and of the saved one, and SAVE_MAP without a path, and checks the replies, the status'
# save counters and the map ids (the new map's, then the saved one's again).
#   lcm_command_e2e.sh WORKDIR ALE_RENDER ALE_SLAMD CLASSPATH [EMULATOR...]
# Rendering runs natively when ALE_RENDER (environment) names the host's ale-render.
set -euo pipefail
work=$1 render=$2 slamd=$3 classpath=$4
shift 4
emulator=("$@")  # qemu-arm for the armhf daemon; empty on the host
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
render_args=(--out "$work/seq" --frames 120 --fps 15 --width 320 --height 240 --supersample 1 --seed 3)
if [ -x "${ALE_RENDER:-}" ]; then "$ALE_RENDER" "${render_args[@]}" >/dev/null; else "${emulator[@]}" "$render" "${render_args[@]}" >/dev/null; fi

pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

# The hub on a free port (the kernel picks one; python3 is not needed: bash asks java).
port=$(( 20000 + ($$ % 20000) ))
for try in 1 2 3 4 5; do
  java -cp "$classpath" lcm.lcm.TCPService "$port" >"$work/hub.log" 2>&1 &
  hub=$!
  # up when it accepts a connection, gone when the port was taken
  for _ in $(seq 50); do
    (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null && break
    kill -0 "$hub" 2>/dev/null || break
    sleep 0.1
  done
  if kill -0 "$hub" 2>/dev/null && (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null; then break; fi
  kill "$hub" 2>/dev/null || true
  port=$((port + 7))
done
kill -0 "$hub" 2>/dev/null || { cat "$work/hub.log"; fail "no LCM TCPService hub could start"; }
pids+=("$hub")
url="tcpq://127.0.0.1:$port"

# 4 KB of noise where a map file should be
head -c 4096 /dev/urandom >"$work/corrupt.alemap"
java -cp "$classpath" AleLcmCommandCheck "$url" 120 "$work/home.alemap" "$work/corrupt.alemap" >"$work/client.log" 2>&1 &
client=$!
pids+=("$client")
for _ in $(seq 100); do grep -q "ready" "$work/client.log" && break; sleep 0.1; done
grep -q "ready" "$work/client.log" || { cat "$work/client.log"; fail "the controller did not subscribe"; }

"${emulator[@]}" "$slamd" --replay "$work/seq" --lcm-url "$url" 2>"$work/daemon.log" ||
  { cat "$work/daemon.log"; fail "ale-slamd exited with $?"; }
# the replies come while the daemon runs; a controller still waiting 10 s after it ended failed
for _ in $(seq 100); do kill -0 "$client" 2>/dev/null || break; sleep 0.1; done
kill -0 "$client" 2>/dev/null && { kill "$client"; cat "$work/client.log"; cat "$work/daemon.log"; fail "the controller was still waiting 10 s after the daemon ended"; }
status=0
wait "$client" || status=$?
cat "$work/client.log"
grep "commands\|command \|map reset\|map saved\|map file\|ale-slamd: frames" "$work/daemon.log" || true
[ "$status" = 0 ] || fail "the controller's checks failed (exit $status)"
grep -q "commands 6 rejected 3 " "$work/daemon.log" || fail "the daemon did not count 6 commands, 3 rejected"
[ -f "$work/home.alemap" ] || fail "SAVE_MAP wrote no $work/home.alemap"
[ -f "$work/corrupt.alemap.refused" ] && fail "a refused LOAD_MAP moved the file aside (only map.load at start does)"
grep -q "0 publish errors" "$work/daemon.log" || fail "the daemon could not publish on $url"
echo "lcm_command_e2e: PASS"
