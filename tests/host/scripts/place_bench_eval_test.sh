#!/usr/bin/env bash
# scripts/place-bench-eval.py on a made-up run whose answer is known: a ground truth of 100 frames,
# an estimate in two maps, each the ground truth under its own similarity (scale, rotation,
# translation), a reset between them, one relocalised frame, and a blackout before the second map.
# Each map aligned on its own fits exactly; as one map it does not.
#   place_bench_eval_test.sh SOURCE_DIR ALE_EVAL
set -euo pipefail
src=$1
ale_eval=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/renders/seq/mav0/cam0" "$work/runs"
python3 - "$work" <<'PY'
import math, sys
work = sys.argv[1]
t0 = 1700000000.0
gt = []
for k in range(100):
    a = 0.08 * k
    gt.append((t0 + k / 15.0, 2.0 + 1.5 * math.cos(a), 2.0 + 1.0 * math.sin(a), 0.09 + 0.01 * math.sin(3 * a)))
with open(work + "/renders/seq/groundtruth.txt", "w") as f:
    f.write("# timestamp tx ty tz qx qy qz qw\n")
    for t, x, y, z in gt:
        f.write("%.9f %.9f %.9f %.9f 0 0 0 1\n" % (t, x, y, z))
with open(work + "/renders/seq/mav0/cam0/data.csv", "w") as f:
    f.write("#timestamp [ns],filename\n")
    for t, *_ in gt:
        f.write("%d,%d.png\n" % (round(t * 1e9), round(t * 1e9)))
def sim(p, s, yaw, tr):
    c, n = math.cos(yaw), math.sin(yaw)
    x, y, z = p[1] - 2.0, p[2] - 2.0, p[3]
    return (p[0], s * (c * x - n * y) + tr[0], s * (n * x + c * y) + tr[1], s * z + tr[2])
# Frames 0-4 initialise, 5-44 map 0, 45-49 lost (light off), a reset, 50-99 map 1.
with open(work + "/runs/seq.tum", "w") as f:
    f.write("# timestamp tx ty tz qx qy qz qw (camera in the map frame, TUM)\n# map 0\n")
    for p in gt[5:45]:
        f.write("%.9f %.9f %.9f %.9f 0 0 0 1\n" % sim(p, 0.5, 0.3, (1.0, -2.0, 0.5)))
    f.write("# map 1\n")
    for p in gt[50:100]:
        f.write("%.9f %.9f %.9f %.9f 0 0 0 1\n" % sim(p, 2.0, -1.2, (-3.0, 0.0, 1.0)))
with open(work + "/runs/seq.frames.csv", "w") as f:
    f.write("#timestamp_ns,sequence,state,map_id\n")
    for k, p in enumerate(gt):
        state = "initializing" if k < 5 else "lost" if 45 <= k < 50 else "relocalized" if k == 70 else "tracking"
        f.write("%d,%d,%s,%d\n" % (round(p[0] * 1e9), k, state, 0 if k < 50 else 1))
PY
out=$(python3 "$src/scripts/place-bench-eval.py" --eval "$ale_eval" --renders "$work/renders" --runs "$work/runs" \
      "seq|blackout:3.0,0.2")
echo "$out"
row=$(grep '^| seq |' <<<"$out")
IFS='|' read -r _ name frames posed resets maps reloc ate ate_pct ate_map ate_map_pct back err same render note <<<"$row"
fail=0
check() { if [ "$(echo $2)" != "$3" ]; then echo "FAIL: $1 is '$(echo $2)', expected '$3'"; fail=1; fi; }
check frames "$frames" 100
check "posed %" "$posed" 94.7      # 90 poses over the 95 frames from the first pose on
check resets "$resets" 1
check maps "$maps" 2
check reloc "$reloc" 1
check "ATE/map cm" "$ate_map" 0.0  # each map fits exactly
check "back s" "$back" 0.13       # light back at 3.2 s, first pose at frame 50 (3.333 s)
check "same map" "$same" no
# As one map, the two frames do not fit: far from zero.
awk -v a="$(echo $ate)" 'BEGIN { exit !(a > 10.0) }' || { echo "FAIL: ATE as one map is $ate cm"; fail=1; }
# The pose after the blackout is in another frame than map 0: a large error in map 0's frame.
awk -v e="$(echo $err)" 'BEGIN { exit !(e > 10.0) }' || { echo "FAIL: error after the blackout is $err cm"; fail=1; }
exit $fail
