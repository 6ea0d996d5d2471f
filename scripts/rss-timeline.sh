#!/usr/bin/env bash
# Runs a replay and samples its memory as it goes: once a second, one line "frames rss_kb" into
# OUT (the frame log's rows written so far, the process's resident set from /proc), so the RSS
# can be read against the run's own time (frames / fps) on a host that replays faster or slower
# than the camera. When COMMAND is a wrapper (/usr/bin/time -v ...), its child is sampled.
# Exit status: the command's.
#
#   scripts/rss-timeline.sh OUT FRAME_LOG -- COMMAND [ARGS...]
#   scripts/rss-timeline.sh --report OUT FPS      RSS at the end of minute 1 and the most after it
set -uo pipefail

if [ "${1:-}" = --report ]; then
  [ $# -eq 3 ] || { echo "usage: rss-timeline.sh --report OUT FPS" >&2; exit 2; }
  awk -v fps="$3" '
    { f = $1; r = $2 / 1024.0; if (r > peak) peak = r
      if (f >= 60 * fps) { if (!at1) at1 = r; if (r > after) after = r; if (!low || r < low) low = r } }
    END { if (!at1) { print "rss: the run is shorter than a minute"; exit 1 }
          printf "rss_mb minute1 %.1f after_minute1 min %.1f max %.1f (+%.1f) peak %.1f\n", at1, low, after, after - at1, peak }' "$2"
  exit $?
fi
[ $# -ge 4 ] && [ "$3" = -- ] || { echo "usage: rss-timeline.sh OUT FRAME_LOG -- COMMAND [ARGS...]" >&2; exit 2; }
out=$1 log=$2
shift 3
: > "$out" || exit 1
"$@" &
pid=$!
while kill -0 "$pid" 2>/dev/null; do
  # a wrapper's (/usr/bin/time's) child is the replay
  target=$(pgrep -P "$pid" | head -1)
  rss=$(awk '/^VmRSS:/ {print $2}' "/proc/${target:-$pid}/status" 2>/dev/null)
  rows=0
  [ -f "$log" ] && rows=$(($(wc -l < "$log") - 1))
  [ -n "$rss" ] && echo "$((rows < 0 ? 0 : rows)) $rss" >> "$out"
  sleep 1
done
wait "$pid"
