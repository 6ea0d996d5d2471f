#!/usr/bin/env bash
# scripts/odometry-bench-eval.py on made-up runs of a tiny rendered square (160x120, 10 s, a 1 s
# blackout at 4 s, `normal` odometry) whose answers are known:
#   fused  = the ground truth scaled by 1.02 about its first position, the first 5 frames unposed:
#            Sim(3) ATE 0, scale error |1 - 1/1.02| = 1.96 %, posed (N - 5) / N
#   vision = the ground truth scaled by 0.5, every other pose 1 cm higher, every frame posed;
#   two relocalised frames and one map change in the fused frame log.
# The Sim(3) ATE of vision, the odometry's and the fused metric ATE are measured by ale-eval
# itself: the table must carry them and their ratios, and the last dark frame's error (ale-eval ate
# --at-time at lighting.csv's last blackout row).
#   odometry_bench_eval_test.sh SOURCE_DIR ALE_RENDER ALE_EVAL
set -euo pipefail
src=$1 render=$2 eval=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
seq=$work/renders/seq
mkdir -p "$work/runs"
"$render" --out "$seq" --trajectory square --turn-rate 90 --duration 10 --fps 15 --width 160 --height 120 \
  --supersample 1 --blackout 4,1 >/dev/null
python3 - "$seq/groundtruth.txt" "$work/runs/seq" <<'PY'
import sys
gt, run = sys.argv[1], sys.argv[2]
rows = [l.split() for l in open(gt) if l.strip() and not l.startswith("#")]
x0 = [float(v) for v in rows[0][1:4]]
with open(run + ".fused.tum", "w") as f:
    for r in rows[5:]:
        p = [x0[i] + 1.02 * (float(r[1 + i]) - x0[i]) for i in range(3)]
        f.write("%s %.9f %.9f %.9f %s\n" % (r[0], p[0], p[1], p[2], " ".join(r[4:8])))
with open(run + ".vision.tum", "w") as f:
    for k, r in enumerate(rows):
        p = [0.5 * float(r[1 + i]) for i in range(3)]
        p[2] += 0.01 * (k % 2)
        f.write("%s %.9f %.9f %.9f %s\n" % (r[0], p[0], p[1], p[2], " ".join(r[4:8])))
for mode in ("fused", "vision"):
    with open(run + "." + mode + ".frames.csv", "w") as f:
        f.write("#timestamp_ns,sequence,state,map_id\n")
        for k, r in enumerate(rows):
            state = "relocalized" if mode == "fused" and k in (30, 31) else "tracking"
            f.write("%d,%d,%s,%d\n" % (round(float(r[0]) * 1e9), k, state, 0 if k < 50 else 1))
PY
set +e
table=$(python3 "$src/scripts/odometry-bench-eval.py" --eval "$eval" --renders "$work/renders" --runs "$work/runs" \
  "seq|blackout:4,1")
status=$?
set -e
echo "$table"
[ $status = 0 ] || fail "exit $status"
row=$(echo "$table" | grep '^| seq |') || fail "no row for seq"
IFS='|' read -r _ name path odo_cm odo_pct vis_pct vis_posed fused_cm fused_pct fused_sim3 scale_err posed resets reloc f_o f_v note <<< "$row"
trim() { echo "$1" | tr -d ' '; }
gt=$seq/groundtruth.txt
n=$(grep -vc '^#' "$gt")
ate() { "$eval" ate --gt "$gt" --est "$1" --align "$2" "${@:3}" | sed -n 's/^ate_rmse //p'; }
"$eval" odometry --dataset "$seq" --out "$work/odo.tum" --times frames >/dev/null
expect() {  # expect COLUMN GOT WANT
  [ "$(trim "$2")" = "$3" ] || fail "$1: '$(trim "$2")', expected '$3'"
}
expect "odo cm" "$odo_cm" "$(awk -v v="$(ate "$work/odo.tum" se3)" 'BEGIN { printf "%.1f", 100 * v }')"
expect "fused cm" "$fused_cm" "$(awk -v v="$(ate "$work/runs/seq.fused.tum" se3)" 'BEGIN { printf "%.1f", 100 * v }')"
expect "fused Sim3 %" "$fused_sim3" "0.000"
expect "scale err %" "$scale_err" "1.96"
expect "posed %" "$posed" "$(awk -v n="$n" 'BEGIN { printf "%.1f", 100 * (n - 5) / n }')"
expect "vis posed %" "$vis_posed" "100.0"
expect "resets" "$resets" "1"
expect "reloc" "$reloc" "2"
f=$(ate "$work/runs/seq.fused.tum" se3); o=$(ate "$work/odo.tum" se3)
expect "fused/odo" "$f_o" "$(awk -v f="$f" -v o="$o" 'BEGIN { printf "%.2f", f / o }')"
expect "vs vision" "$f_v" "0.00"
vis=$(ate "$work/runs/seq.vision.tum" sim3)
p=$(trim "$path")
expect "vis Sim3 %" "$vis_pct" "$(awk -v v="$vis" -v p="$p" 'BEGIN { printf "%.2f", 100 * v / p }')"
# The last dark frame: lighting.csv's last blackout row, its error after the fused run's SE(3) alignment.
last=$(awk -F, '$2 == "blackout" { t = $1 } END { print t }' "$seq/lighting.csv")
t0=$(sed -n 2p "$seq/mav0/cam0/data.csv" | cut -d, -f1)
dark=$("$eval" ate --gt "$gt" --est "$work/runs/seq.fused.tum" --at-time "$(awk -v t="$last" 'BEGIN { printf "%.9f", t * 1e-9 }')" |
  sed -n 's/^at_time_error_m //p')
want="the last dark frame ($(awk -v t="$last" -v z="$t0" 'BEGIN { printf "%.2f", (t - z) * 1e-9 }') s) is off by $(awk -v e="$dark" 'BEGIN { printf "%.1f", 100 * e }') cm"
echo "$table" | grep -qF "$want" || fail "blackout line: expected '$want'"
echo "odometry_bench_eval_test: ok"
