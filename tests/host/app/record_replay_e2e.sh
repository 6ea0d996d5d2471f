#!/usr/bin/env bash
# ale-slamd's recorder end to end (in the armhf build the daemon runs under qemu-arm):
#   1. a replay with --set recorder.dir=REC writes one EuRoC sequence of every frame it was given
#      and of every wheel odometry sample it handed to the core, and says so in its closing line;
#   2. `ale-slamd --replay` of that sequence, odometry and all, gives the source replay's
#      trajectory byte for byte;
#   3. a second run into the same folder adds a second sequence, and a cap of 1 MiB drops the
#      first (the oldest) to make room;
#   4. recorder.dir below a regular file: the error is logged, the replay still tracks, exit 0.
#
#   record_replay_e2e.sh WORK_DIR SLAMD RENDER FRAMES [EMULATOR...]
#
# The input is a sequence ale-render makes (one that initialises and tracks); when ALE_RENDER
# names the host's ale-render (the armhf build's ctest sets it) it renders natively.
set -euo pipefail
work=$1 slamd=$2 render=$3 frames=$4
shift 4
emu=("$@")
run() { "${emu[@]}" "$@"; }
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
dataset=$work/seq
render_args=(--out "$dataset" --frames "$frames" --fps 15 --supersample 1 --seed 3 --overwrite)
if [ -x "${ALE_RENDER:-}" ]; then "$ALE_RENDER" "${render_args[@]}" >/dev/null; else run "$render" "${render_args[@]}" >/dev/null; fi
rec=$work/rec
common=(--lcm-url memq:// --max-frames "$frames")

# 1 and 2.
run "$slamd" --replay "$dataset" "${common[@]}" --set recorder.dir="$rec" --trajectory "$work/source.tum" \
  2>"$work/source.log" || { cat "$work/source.log"; fail "the recording replay exited with $?"; }
cat "$work/source.log"
grep -q "recorder recording: $frames frames recorded, 0 not recorded" "$work/source.log" || fail "no recorder line"
seqs=("$rec"/*/)
[ "${#seqs[@]}" = 1 ] || fail "expected one sequence in $rec, found ${#seqs[@]}"
first=${seqs[0]%/}
listed=$(grep -vc '^#' "$first/mav0/cam0/data.csv")
[ "$listed" = "$frames" ] || fail "$first lists $listed frames, not $frames"
# The samples the source replay handed over are the ones recorded (none lost), and the replay of
# the recording uses them.
handed=$(sed -n 's/.*recorder recording: .* \([0-9]*\) odometry samples recorded, 0 not recorded.*/\1/p' "$work/source.log")
[ "${handed:-0}" -gt 0 ] || fail "no odometry samples recorded"
samples=$(grep -vc '^#' "$first/mav0/odometry0/data.csv")
[ "$samples" = "$handed" ] || fail "$first lists $samples odometry samples, not $handed"
run "$slamd" --replay "$first" "${common[@]}" --trajectory "$work/recording.tum" 2>"$work/recording.log" ||
  { cat "$work/recording.log"; fail "the replay of the recording exited with $?"; }
# The comparison needs poses: at least half the frames tracked (measured: 35 of 40 on the host).
tracked=$(sed -n 's/.*frames [0-9]* tracked \([0-9]*\) .*/\1/p' "$work/source.log")
[ "${tracked:-0}" -ge $((frames / 2)) ] || fail "${tracked:-no} of $frames frames tracked: the comparison needs poses"
grep -q "odometry: $samples samples from $first/mav0/odometry0/data.csv" "$work/recording.log" ||
  fail "the replay of the recording did not use its odometry"
cmp "$work/source.tum" "$work/recording.tum" || fail "the recording's trajectory differs from the source's"

# 3. The first sequence is larger than 1 MiB, so the second run's cap drops it.
run "$slamd" --replay "$dataset" --lcm-url memq:// --max-frames 3 --set recorder.dir="$rec" --set recorder.max_mb=1 \
  2>"$work/capped.log" || { cat "$work/capped.log"; fail "the capped run exited with $?"; }
grep -q "dropped the oldest sequence $first" "$work/capped.log" || { cat "$work/capped.log"; fail "the first sequence was not dropped"; }
[ ! -e "$first" ] || fail "$first is still there"
left=("$rec"/*/)
[ "${#left[@]}" = 1 ] && case ${left[0]} in */000002_*) ;; *) false ;; esac || fail "expected only sequence 000002_ in $rec"

# 4.
echo x >"$work/a-file"
run "$slamd" --replay "$dataset" --lcm-url memq:// --max-frames 3 --set recorder.dir="$work/a-file/rec" \
  2>"$work/bad.log" || { cat "$work/bad.log"; fail "an unusable recorder.dir stopped the daemon"; }
grep -q "recorder.dir $work/a-file/rec: cannot create" "$work/bad.log" || { cat "$work/bad.log"; fail "no error naming recorder.dir"; }
grep -q "frames 3 tracked" "$work/bad.log" || fail "the replay did not go on"
echo "record_replay_e2e: $frames frames recorded and replayed to the same trajectory; $samples odometry samples with them; cap and bad folder handled"
