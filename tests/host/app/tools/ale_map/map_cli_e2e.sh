#!/usr/bin/env bash
# ale-map on a map the daemon saved: a short rendered run (90 frames, 320x240) replayed with
# --save-map; then `check` and `info` on it exit 0 with what the daemon logged (keyframes,
# landmarks, bytes) and the render's camera; `--camera-from` the replayed dataset passes and from
# a 160x120 render is refused as another camera; a store of 2 keyframes refuses it; `resave --count 3` prints three saves and leaves DST
# and DST.bak, both checked good and byte-identical to the source; a copy one byte short is refused
# as truncated and one with a byte flipped as a checksum mismatch (exit 1 both); mutants of every
# region of the file (mutate_map.py) are refused by ale-map and the daemon (below).
#
#   map_cli_e2e.sh WORK_DIR ALE_MAP ALE_RENDER ALE_SLAMD
set -euo pipefail
work=$1 map=$2 render=$3 slamd=$4
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
"$render" --out "$work/seq" --frames 90 --fps 15 --width 320 --height 240 --supersample 1 >"$work/render.log"
"$slamd" --replay "$work/seq" --lcm-url memq:// --save-map "$work/home.alemap" 2>"$work/slamd.log" ||
  { cat "$work/slamd.log" >&2; fail "ale-slamd exited with $?"; }
saved=$(sed -n 's/.*map saved to .* in .* ms: 1 map(s), \([0-9]*\) keyframes, \([0-9]*\) landmarks, \([0-9]*\) bytes.*/\1 \2 \3/p' "$work/slamd.log")
[ -n "$saved" ] || { cat "$work/slamd.log" >&2; fail "the daemon logged no saved map"; }
read -r kf lm bytes <<<"$saved"
saved="keyframes=$kf landmarks=$lm bytes=$bytes"
[ "$kf" -ge 3 ] || fail "the saved map has $kf keyframes"

out=$("$map" check "$work/home.alemap") || fail "check exited with $?: $out"
[[ $out =~ version=1\ bytes=$bytes\ maps=1\ keyframes=$kf\ landmarks=$lm\ current_map=[0-9]+\ check_ms=[0-9.]+\ load_ms=[0-9.]+ ]] ||
  fail "check printed '$out', the daemon saved $saved"
out=$("$map" info "$work/home.alemap") || fail "info exited with $?: $out"
grep -q "^camera: 320x240 fx=" <<<"$out" || fail "info shows no 320x240 camera: $out"
grep -q "^map id=[0-9]* (current) metric=[01] keyframes=$kf landmarks=$lm keyframe_times_s=" <<<"$out" ||
  fail "info shows no current map of $kf keyframes: $out"
# the camera of the replayed dataset is the file's; another resolution's is refused, saying so
"$map" check "$work/home.alemap" --camera-from "$work/seq" >/dev/null || fail "the file's own dataset's camera is refused"
"$render" --out "$work/small" --frames 3 --fps 15 --width 160 --height 120 --supersample 1 >"$work/render_small.log"
if out=$("$map" check "$work/home.alemap" --camera-from "$work/small" 2>&1); then fail "a 160x120 camera took the file"; fi
grep -q "made with another camera (320x240, .*this one 160x120" <<<"$out" || fail "the camera refusal: $out"
# a store too small for it is refused as the daemon's would be
if out=$("$map" check "$work/home.alemap" --set slam.capacity.max_keyframes=2 2>&1); then fail "a 2-keyframe store took $kf keyframes"; fi
grep -q "capacity" <<<"$out" || fail "the capacity refusal does not say so: $out"

out=$("$map" resave "$work/home.alemap" "$work/copy.alemap" --count 3) || fail "resave exited with $?: $out"
[ "$(grep -c "^save=[123]/3 map=$work/copy.alemap bytes=$bytes save_ms=[0-9.]*$" <<<"$out")" = 3 ] ||
  fail "resave did not print three saves: $out"
cmp -s "$work/home.alemap" "$work/copy.alemap" || fail "the re-saved file differs from the source"
cmp -s "$work/home.alemap" "$work/copy.alemap.bak" || fail "the backup differs from the source"
"$map" check "$work/copy.alemap.bak" >/dev/null || fail "the backup is refused"
[ ! -e "$work/copy.alemap.tmp" ] || fail "resave left copy.alemap.tmp"

head -c $((bytes - 1)) "$work/home.alemap" >"$work/short.alemap"
if out=$("$map" check "$work/short.alemap" 2>&1); then fail "a truncated file passed: $out"; else status=$?; fi
[ "$status" = 1 ] || fail "a truncated file exited with $status"
grep -q "short.alemap: refused: corrupt data: .*truncated: $((bytes - 1)) bytes, the header says $bytes" <<<"$out" ||
  fail "the truncated file's refusal: $out"

cp "$work/home.alemap" "$work/flipped.alemap"
printf '\x55' | dd of="$work/flipped.alemap" bs=1 seek=$((bytes / 2)) conv=notrunc status=none
if cmp -s "$work/home.alemap" "$work/flipped.alemap"; then
  printf '\xaa' | dd of="$work/flipped.alemap" bs=1 seek=$((bytes / 2)) conv=notrunc status=none
fi
if out=$("$map" check "$work/flipped.alemap" 2>&1); then fail "an altered file passed: $out"; else status=$?; fi
[ "$status" = 1 ] || fail "an altered file exited with $status"
grep -q "refused: corrupt data: .*checksum mismatch" <<<"$out" || fail "the altered file's refusal: $out"
# Every region of the saved file (header, each section, table, trailer) altered at its first,
# middle and last byte and cut in its middle, and the header made to say format version 2 or
# another vocabulary (its checksums right again): ale-map refuses each (the vocabulary is the
# daemon's to judge); the daemon refuses each middle flip, the version and the vocabulary, keeps
# the file as FILE.refused byte for byte and starts an empty map.
mutants=$(python3 "$(dirname "$0")/mutate_map.py" "$work/home.alemap" "$work/mutants") || fail "mutate_map.py failed"
n=0
while read -r file expected; do
  name=$(basename "$file" .alemap)
  n=$((n + 1))
  if [ "$name" != header-other_vocabulary ]; then
    if out=$("$map" check "$file" 2>&1); then fail "$name passed ale-map check: $out"; else status=$?; fi
    [ "$status" = 1 ] || fail "$name: ale-map check exited with $status"
    grep -Eq "$expected" <<<"$out" || fail "$name: ale-map check said '$out', expected /$expected/"
  fi
  case $name in *-flip_middle | header-version_2 | header-other_vocabulary) ;; *) continue ;; esac
  cp "$file" "$work/mutant.alemap"
  rm -f "$work/mutant.alemap.refused"
  # the load comes with the first frame (the core is built on it): one frame is enough
  "$slamd" --replay "$work/seq" --max-frames 1 --lcm-url memq:// --load-map "$work/mutant.alemap" 2>"$work/mutant.log" ||
    { cat "$work/mutant.log" >&2; fail "$name: ale-slamd exited with $?"; }
  grep -Eq "map file $work/mutant.alemap $expected.*moved to $work/mutant.alemap.refused" "$work/mutant.log" ||
    { cat "$work/mutant.log" >&2; fail "$name: the daemon's refusal does not match /$expected/"; }
  cmp -s "$file" "$work/mutant.alemap.refused" || fail "$name: the refused file was not kept as it was"
  grep -q "starting an empty map" "$work/mutant.log" || fail "$name: the daemon did not start an empty map"
done <<<"$mutants"
[ "$n" -ge 22 ] || fail "only $n mutants"
echo "map_cli_e2e: ok ($kf keyframes, $lm landmarks, $bytes bytes; $n mutants refused)"
