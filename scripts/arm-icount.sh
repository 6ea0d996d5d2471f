#!/usr/bin/env bash
# Counts the guest ARM instructions an armhf program executes, per frame and per stage of the
# frame path, at qemu's normal speed: the same count as ../shared/tools/arm_icount.py (which
# parses qemu's exec log at about 1 M instructions a second), from our TCG plugin
# (scripts/icount/) in a qemu-arm built with plugins from Debian's source (`setup-deps.sh icount`,
# cached; the first run takes several minutes). A measurement tool: neither the build nor the
# tests use it. docs/performance.md ("Whole pipeline") has the figures and how they were taken.
#
#   scripts/arm-icount.sh [--top N] [--out DIR] [--program-output FILE] [--check] -- PROGRAM [ARGS...]
#   e.g. scripts/arm-icount.sh --top 15 -- build/armhf/bin/ale-slamd --replay DIR --trajectory T.tum
#
# Prints `guest_instructions N  exit RC` (arm_icount.py's line), then, when the program ran the
# frame path (core/base/stage_probe.h), the frames and per stage the mean, median, 95th percentile
# and maximum instructions per frame: front end (its six stages), track, map, the frame path, what
# ran between frames (replay I/O, logs) and the whole process per frame without start-up. --top N:
# the N functions with the most instructions in the front end, track, map and outside (by the
# symbol of each block's first instruction, as arm_icount.py --top). --out DIR keeps the raw report
# and the per-frame CSV (default: a temporary directory). The program's output goes to /dev/null,
# as with arm_icount.py (its code paths depend on it: a terminal, a pipe), or to FILE.
# The count depends on the program's environment too (glibc's start-up reads it): the program runs
# with this script's environment without $_ (bash's path of the command it starts) and with
# LC_CTYPE=C.UTF-8 when no locale is set (what python3 adds for its children), so that --check
# can run ../shared/tools/arm_icount.py (slow) on the same command in the same environment: it
# prints both totals, and the functions whose counts differ.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
die() { printf 'arm-icount: error: %s\n' "$*" >&2; exit 2; }

top=0 out= program_output=/dev/null check=0
while [ $# -gt 0 ]; do
  case "$1" in
    --top) [ $# -ge 2 ] || die "--top needs a number"; top=$2; shift 2 ;;
    --out) [ $# -ge 2 ] || die "--out needs a directory"; out=$2; shift 2 ;;
    --program-output) [ $# -ge 2 ] || die "--program-output needs a file"; program_output=$2; shift 2 ;;
    --check) check=1; shift ;;
    --) shift; break ;;
    -h|--help) sed -n '2,23p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) break ;;
  esac
done
[ $# -gt 0 ] || die "no program (usage: arm-icount.sh [--top N] [--out DIR] -- PROGRAM [ARGS...])"
case "$top" in ''|*[!0-9]*) die "--top '$top' is not a number" ;; esac
[ -f "$1" ] || die "no program '$1'"

setup_log=$(mktemp)
prefix=$("$root/scripts/setup-deps.sh" icount 2>"$setup_log" | sed -n 's/^ALE_DEPS_icount=//p') || true
[ -x "$prefix/bin/qemu-arm" ] || { cat "$setup_log" >&2; die "setup-deps.sh icount gave no qemu-arm"; }
rm -f "$setup_log"

# The plugin, rebuilt when its sources change.
plugin_dir=$root/build/icount
plugin=$plugin_dir/libicount.so
src=$root/scripts/icount
if [ ! -f "$plugin" ] || [ -n "$(find "$src" -newer "$plugin" -name '*.[ch]')" ]; then
  mkdir -p "$plugin_dir"
  cc -std=c11 -O2 -Wall -Wextra -Werror -shared -fPIC -fvisibility=hidden -I"$prefix/include" \
    -o "$plugin.tmp" "$src/icount_plugin.c" "$src/tally.c" -lpthread || die "cannot build the plugin"
  mv "$plugin.tmp" "$plugin"
fi

if [ -n "$out" ]; then mkdir -p "$out"; else out=$(mktemp -d); trap 'rm -rf "$out"' EXIT; fi
functions=off
if [ "$top" -gt 0 ] || [ "$check" = 1 ]; then functions=on; fi
[ -n "${LC_ALL:-}${LC_CTYPE:-}${LANG:-}" ] || export LC_CTYPE=C.UTF-8
[ "$check" = 0 ] || [ "$program_output" = /dev/null ] || die "--check compares runs with the output to /dev/null"
rc=0
env -u _ "$prefix/bin/qemu-arm" -plugin "$plugin,out=$out/report.txt,frames=$out/frames.csv,functions=$functions" "$@" \
  >"$program_output" 2>&1 || rc=$?
[ -f "$out/report.txt" ] || die "the plugin wrote no report (qemu exit $rc)"

report=$out/report.txt
total=$(awk '$1 == "total_instructions" {print $2}' "$report")
echo "guest_instructions $total  exit $rc"
vcpus=$(awk '$1 == "vcpus" {print $2}' "$report")
[ "$vcpus" = 1 ] || echo "warning: $vcpus guest threads: the counts are exact for one thread only"
! grep -q '^error' "$report" || echo "warning: $(grep '^error' "$report")"
frames=$(awk '$1 == "frames" {print $2}' "$report")
if [ "$check" = 1 ]; then
  ref=${ALE_ARM_ICOUNT_PY:-$root/../shared/tools/arm_icount.py}
  [ -f "$ref" ] || die "no $ref"
  env -u _ /usr/bin/python3 "$ref" --top 1000000 -- "$@" >"$out/reference.txt"
  echo "check: arm_icount.py $(head -n 1 "$out/reference.txt")"
  tail -n +2 "$out/reference.txt" | awk '{print $2, $1}' | sort >"$out/reference_functions.txt"
  awk '$1 == "function" {c[$4] += $3} END {for (k in c) print k, c[k]}' "$out/report.txt" | sort >"$out/functions.txt"
  join -a 1 -a 2 -e 0 -o 0,1.2,2.2 "$out/reference_functions.txt" "$out/functions.txt" >"$out/joined.txt"
  echo "check: $(wc -l <"$out/joined.txt") functions, $(awk '$2 != $3' "$out/joined.txt" | wc -l) with other counts"
  awk '$2 != $3 {printf "  %s arm_icount.py %d plugin %d\n", $1, $2, $3}' "$out/joined.txt" | head -n 20
fi
[ "$frames" -gt 0 ] || exit "$rc"

# Slots (core/frontend/frame_path.h): 1-6 the front end's stages, then the appended ones
# (SlamPipeline: 7 map_ba, the local BA deferred from the last keyframe, 8 track, 9 map; map below
# is 7 + 9); 0 between frames.
prologue=$(awk '$1 == "prologue" {print $2}' "$report")
echo "frames $frames  start-up before the first frame $prologue  per frame without start-up $(( (total - prologue) / frames ))"
# One column per quantity, then mean / median / p95 / max of each (nearest rank).
awk -F, 'NR > 1 {
    fe = $3 + $4 + $5 + $6 + $7 + $8; map = $9 + $11; path = fe + $10 + map
    for (s = 12; s <= NF; ++s) path += $s
    print fe, $10, map, path, $2, path + $2, $3, $4, $5, $6, $7, $8
  }' "$out/frames.csv" >"$out/columns.txt"
labels=(front_end track map frame_path between_frames whole grade pyramid enhance detect distribute describe)
printf '%-16s %14s %14s %14s %14s\n' "per frame" mean median p95 max
for i in "${!labels[@]}"; do
  col=$((i + 1))
  cut -d' ' -f$col "$out/columns.txt" | sort -n | awk -v label="${labels[$i]}" '
    { v[NR] = $1; sum += $1 }
    END {
      p50 = int(NR * 0.50 + 0.999999); p95 = int(NR * 0.95 + 0.999999)
      printf "%-16s %14.0f %14d %14d %14d\n", label, sum / NR, v[p50], v[p95], v[NR]
    }'
done

if [ "$top" -gt 0 ]; then
  # (awk, not head, keeps the first N: head's early exit could kill sort with SIGPIPE, which
  # pipefail turned into the script's silent end after the first groups)
  for group in front_end track map outside; do  # outside: start-up included
    case $group in front_end) slots="1 2 3 4 5 6" ;; track) slots=8 ;; map) slots="7 9" ;; outside) slots=0 ;; esac
    echo "top functions, $group (instructions per frame, share of the group):"
    awk -v slots="$slots" -v frames="$frames" '
      BEGIN { n = split(slots, s, " "); for (i = 1; i <= n; ++i) want[s[i]] = 1 }
      $1 == "function" && ($2 in want) { name = $4; for (i = 5; i <= NF; ++i) name = name " " $i; c[name] += $3; sum += $3 }
      END { for (k in c) printf "%d %.4f %s\n", c[k] / frames, c[k] / sum, k }' "$report" |
      sort -k1,1nr | awk -v n="$top" 'NR <= n' | c++filt | awk '{ name = $3; for (i = 4; i <= NF; ++i) name = name " " $i; printf "  %12d  %5.1f%%  %s\n", $1, 100 * $2, name }'
  done
fi
exit "$rc"
