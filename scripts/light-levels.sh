#!/usr/bin/env bash
# The wide light-level matching set of issue 13 (docs/features.md, "Matching in the dark"):
#
#   scripts/light-levels.sh render DIR [--rooms "A B ..."] [--runs "SEED:START ..."] [--frames N]
#                                      [--supersample K]
#   scripts/light-levels.sh report DIR [ale-features options: --mode M, --set KEY=VALUE, --gaps ...]
#
# `render` writes one ale-render sequence per room, run (noise seed and start time in seconds;
# default "5:6 11:20") and light level into
# DIR/<room>_s<seed>_t<start>_<level> (skipping those already there). Rooms: proc (the default
# procedural textures), proc2 (texture seed 0xA11CE), and chamonix, courbevoie, stlouis (the
# webcam photographs of ../shared/data/lighting/webcam as textures). Levels: normal, normal_dark,
# dark (normal_dark with the analogue gain capped at 3), extremely_dark (the `dark` profile),
# off_on. 16 frames at 15 fps, 1 ray per pixel by default.
# `report` runs `ale-features --match-report` on every sequence of DIR and prints the mean
# inliers per mode, gap, room and level, and per level over all rooms (each sequence weighs the
# same: all have the same number of pairs at a gap).
# Binaries: build/host/bin (ALE_BIN overrides); data: ../shared/data (ALE_DATA_DIR overrides).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${ALE_BIN:-$root/build/host/bin}
data=${ALE_DATA_DIR:-$root/../shared/data}
levels="normal normal_dark dark extremely_dark off_on"

usage() { sed -n '2,18p' "$0" >&2; exit 2; }
[ $# -ge 2 ] || usage
cmd=$1 dir=$2; shift 2

case "$cmd" in
  render)
    rooms="proc proc2 chamonix courbevoie stlouis" runs="5:6 11:20" frames=16 ss=1
    while [ $# -gt 0 ]; do
      case "$1" in
        --rooms) rooms=$2 ;; --runs) runs=$2 ;;
        --frames) frames=$2 ;; --supersample) ss=$2 ;; *) usage ;;
      esac
      shift 2
    done
    mkdir -p "$dir"
    for room in $rooms; do
      case "$room" in
        proc) look=() ;;
        proc2) look=(--texture-seed $((0xA11CE))) ;;
        chamonix|courbevoie|stlouis) look=(--textures "$data/lighting/webcam/$room") ;;
        *) echo "light-levels.sh: unknown room '$room'" >&2; exit 2 ;;
      esac
      for run in $runs; do
        seed=${run%%:*} start=${run#*:}
        [ "$seed" != "$run" ] || { echo "light-levels.sh: --runs wants SEED:START, not '$run'" >&2; exit 2; }
        for level in $levels; do
            case "$level" in
              dark) light=(--light normal_dark --max-gain 3) ;;
              extremely_dark) light=(--light dark) ;;
              *) light=(--light "$level") ;;
          esac
            out=$dir/${room}_s${seed}_t${start}_${level}
            [ -d "$out/mav0" ] && continue
            nice "$bin/ale-render" --out "$out" "${look[@]}" "${light[@]}" --seed "$seed" --start "$start" \
              --frames "$frames" --fps 15 --supersample "$ss" | grep "mean grey" | sed "s|^|$out: |"
        done
      done
    done
    ;;
  report)
    seqs=$(find "$dir" -mindepth 1 -maxdepth 1 -type d -name '*_s*_t*_*' | sort)
    [ -n "$seqs" ] || { echo "light-levels.sh: no sequences in $dir (run render first)" >&2; exit 1; }
    # shellcheck disable=SC2086
    nice "$bin/ale-features" --match-report "$@" $seqs | awk -v levels="$levels" '
      {
        n = split($1, p, "/"); name = p[n]
        for (i = 2; i <= NF; ++i) { split($i, kv, "="); f[kv[1]] = kv[2] }
        room = name; sub(/_s[0-9]+_t[0-9.]+_.*/, "", room)
        level = name; sub(/^.*_s[0-9]+_t[0-9.]+_/, "", level)
        key = f["mode"] SUBSEP f["gap"]
        if (!(key in seen)) { seen[key] = 1; keys[++nk] = key }
        if (!((room) in rseen)) { rseen[room] = 1; rooms[++nr] = room }
        s[key, room, level] += f["inliers"]; c[key, room, level] += 1
        s[key, "all", level] += f["inliers"]; c[key, "all", level] += 1
      }
      END {
        nl = split(levels, lv, " ")
        rooms[++nr] = "all"
        for (k = 1; k <= nk; ++k) {
          split(keys[k], mg, SUBSEP)
          printf "mode=%s gap=%s mean inliers\n  %-12s", mg[1], mg[2], "room"
          for (l = 1; l <= nl; ++l) printf " %14s", lv[l]
          printf "\n"
          for (r = 1; r <= nr; ++r) {
            printf "  %-12s", rooms[r]
            for (l = 1; l <= nl; ++l) {
              kk = keys[k] SUBSEP rooms[r] SUBSEP lv[l]
              if (c[kk] > 0) printf " %9.1f (%2d)", s[kk] / c[kk], c[kk]; else printf " %14s", "-"
            }
            printf "\n"
          }
        }
      }'
    ;;
  *) usage ;;
esac
