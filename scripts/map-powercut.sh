#!/usr/bin/env bash
# The map file against a process killed in the middle of a save (docs/daemon.md "Map files"):
#
#   scripts/map-powercut.sh [--runs N] [--count K] [--out DIR]
#
# 1. A map file: one lap of the rendered loop (ale-render --trajectory loop --laps 1, 15 fps,
#    320x240; rendered once into DIR/render) replayed by ale-slamd --save-map DIR/src.alemap.
# 2. Its load and save times measured (three `ale-map check` and three `ale-map resave --count K`
#    whose median wall times bound the kill window), and DIR/dst.alemap saved once, so that it
#    exists before the first kill.
# 3. N times (--runs, default 1000): `ale-map resave DIR/src.alemap DIR/dst.alemap --count 100K`
#    started in the background and killed with SIGKILL after a random delay, uniform over the
#    window measured in 2 (from the end of the process's load to the end of its first K saves, K
#    by --count, default 10; the process would go on saving well past it, so a machine faster or
#    slower than when measured moves the kills among the saves, not out of them); then
#    `ale-map check` on dst.alemap and, if it is refused, on dst.alemap.bak. Outcomes: the file
#    intact (it loads, and is byte-identical to the source: every save writes the same map), the
#    file refused but its backup intact, neither (must be 0; the files are kept in
#    DIR/failed-RUN); and dst.alemap missing (must be 0: it exists from the first save on). A kill that leaves dst.alemap.tmp behind landed between the save's open and
#    its rename: counted as "inside a save".
# Prints one summary line: the counts, the kill delays (min, median, max, in ms after the start),
# the saves completed before the kill and the runs whose process ended before it (none expected).
# Exits 1 when any run had neither file intact or no dst.alemap.
#
# A SIGKILL stops the process at any instruction but keeps what it wrote in the page cache; a power
# cut also loses what was not yet on the disk, which this does not reproduce (the save's fsyncs
# of the file and of the directory are there for that).
# BIN (default build/host/bin) holds ale-render, ale-slamd and ale-map; needs bash 5 (EPOCHREALTIME).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
BIN=${BIN:-$root/build/host/bin}
runs=1000 count=10 out=/tmp/ale-map-powercut
die() { echo "map-powercut: $*" >&2; exit 2; }
while [ $# -gt 0 ]; do
  case $1 in
    --runs) [[ ${2:-} =~ ^[1-9][0-9]*$ ]] || die "--runs needs a whole number >= 1"; runs=$2; shift ;;
    --count) [[ ${2:-} =~ ^[1-9][0-9]{0,3}$ ]] || die "--count needs a whole number from 1 to 9999"; count=$2; shift ;;
    --out) [ -n "${2:-}" ] || die "--out needs a folder"; out=$2; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown option '$1' (see --help)" ;;
  esac
  shift
done
for tool in ale-render ale-slamd ale-map; do
  [ -x "$BIN/$tool" ] || die "$BIN/$tool is missing: build it (scripts/build.sh host Release $tool)"
done
[ -n "${EPOCHREALTIME:-}" ] || die "needs bash 5 (EPOCHREALTIME)"
mkdir -p "$out"
src=$out/src.alemap dst=$out/dst.alemap

# 1. the map file
render_options="--trajectory loop --laps 1 --fps 15 --width 320 --height 240 --supersample 1"
if [ ! -f "$out/render/options.txt" ] || [ "$(cat "$out/render/options.txt")" != "$render_options" ]; then
  rm -rf "$out/render" "$src"
  # shellcheck disable=SC2086  # the options are words
  "$BIN/ale-render" --out "$out/render" $render_options >"$out/render.log" || die "ale-render failed (see $out/render.log)"
  echo "$render_options" >"$out/render/options.txt"
fi
if [ ! -f "$src" ]; then
  "$BIN/ale-slamd" --replay "$out/render" --lcm-url memq:// --save-map "$src" >"$out/slamd.log" 2>&1 ||
    die "ale-slamd failed (see $out/slamd.log)"
fi
grep -h "map saved to" "$out/slamd.log" 2>/dev/null | sed 's/^/map-powercut: /' || true

# 2. save and load times, and the kill window: from the wall time of a whole `ale-map check`
# process (its start and load, as resave's) to that of a whole `resave --count K` (medians of 3)
now_us() { local t=${EPOCHREALTIME/[.,]/}; echo $((10#$t)); }
median3() { printf '%s\n' "$@" | sort -n | sed -n 2p; }
: >"$out/measure.txt"
loads=() walls=()
for _ in 1 2 3; do
  t0=$(now_us)
  "$BIN/ale-map" check "$src" >"$out/check.txt" || die "ale-map check refused the source map: $(cat "$out/check.txt")"
  loads+=($(( $(now_us) - t0 )))
  t0=$(now_us)
  "$BIN/ale-map" resave "$src" "$out/measure.alemap" --count "$count" >>"$out/measure.txt" || die "ale-map resave failed"
  walls+=($(( $(now_us) - t0 )))
done
rm -f "$out"/measure.alemap*
first_us=$(median3 "${loads[@]}") last_us=$(median3 "${walls[@]}")
[ "$last_us" -gt "$first_us" ] || last_us=$((first_us + 1))
save_ms=$(awk -F'save_ms=' '/^save=/ {print $2}' "$out/measure.txt" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
echo "map-powercut: $(cat "$out/check.txt"); save_ms median of $((3 * count)): $save_ms;" \
     "kill window $((first_us / 1000)) to $((last_us / 1000)) ms after the start (medians of 3)"
rm -f "$dst" "$dst.bak" "$dst.tmp"
"$BIN/ale-map" resave "$src" "$dst" --count 1 >/dev/null || die "the first save to $dst failed"

# 3. the kills
intact=0 backup=0 neither=0 missing=0 inside=0 finished=0
: >"$out/kills.txt"  # per run: delay_ms saves_completed tmp_left outcome
for ((run = 1; run <= runs; run++)); do
  rm -f "$dst.tmp"
  delay_us=$(( first_us + (RANDOM * 32768 + RANDOM) % (last_us - first_us) ))
  delay=$(printf '%d.%06d' $((delay_us / 1000000)) $((delay_us % 1000000)))
  t0=$(now_us)
  "$BIN/ale-map" resave "$src" "$dst" --count $((count * 100)) >"$out/resave.txt" 2>&1 &
  pid=$!
  sleep "$delay"
  kill -9 "$pid" 2>/dev/null || true
  killed_us=$(( $(now_us) - t0 ))
  status=0
  wait "$pid" 2>/dev/null || status=$?
  saves=$(grep -c '^save=' "$out/resave.txt" || true)
  tmp=0
  [ -e "$dst.tmp" ] && tmp=1 && inside=$((inside + 1))
  [ "$status" = 0 ] && finished=$((finished + 1))
  [ -e "$dst" ] || missing=$((missing + 1))
  if "$BIN/ale-map" check "$dst" >/dev/null 2>"$out/check.err" && cmp -s "$src" "$dst"; then
    outcome=intact intact=$((intact + 1))
  elif "$BIN/ale-map" check "$dst.bak" >/dev/null 2>>"$out/check.err" && cmp -s "$src" "$dst.bak"; then
    outcome=backup backup=$((backup + 1))
  else
    outcome=neither neither=$((neither + 1))
    mkdir -p "$out/failed-$run"
    cp -p "$dst"* "$out/check.err" "$out/resave.txt" "$out/failed-$run/" 2>/dev/null || true
  fi
  echo "$((killed_us / 1000)).$(printf '%03d' $((killed_us % 1000))) $saves $tmp $outcome" >>"$out/kills.txt"
done 2>>"$out/shell.err"  # bash's "Killed" notices

spread=$(sort -g "$out/kills.txt" | awk '{d[NR]=$1} END {printf "min %.1f median %.1f max %.1f", d[1], d[int((NR+1)/2)], d[NR]}')
saves=$(awk '{n[$2]++} END {for (k in n) printf "%s:%d ", k, n[k]}' "$out/kills.txt" | tr ' ' '\n' | sort -n | tr '\n' ' ')
echo "map-powercut: runs=$runs count=$count intact=$intact backup_intact=$backup neither=$neither missing=$missing" \
     "inside_a_save=$inside finished_before_kill=$finished kill_ms: $spread (window $((first_us / 1000)) to $((last_us / 1000)) ms);" \
     "saves completed before the kill (saves:runs): ${saves% }"
[ "$neither" = 0 ] && [ "$missing" = 0 ]
