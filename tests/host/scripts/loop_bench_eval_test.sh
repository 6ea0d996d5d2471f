#!/usr/bin/env bash
# scripts/loop-bench-eval.py on made-up runs whose answers are known: a ground truth of two laps
# of a 1 m circle (150 frames, 75 a lap). Route `merged`: map 0 from frame 3, lost in a blackout
# (frames 60-69), map 1 (70-89), then back in map 0 (90-149, as after a merge), each map the
# ground truth under its own similarity; frame-log columns `loops` (a running count: 1) and
# `merges` (a count per frame: 1), one relocalised frame. Route `plain`: one map, no loop or
# merge columns, the daemon's last line says `loops_closed 3 loops_refused 1 merges 2 merges_refused
# 5`. Route `lines`: the same run, its log has two `loop closed at` and two `loop refused at`
# lines. Route `daemon`: the same run with the columns ale-slamd writes, running counts since start
# (`loops` 1, `merges` 2, `merges_refused` 4 at the end), and a last line that says otherwise.
#   loop_bench_eval_test.sh SOURCE_DIR ALE_EVAL
set -euo pipefail
src=$1
ale_eval=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/runs"
python3 - "$work" "$src/tests/host/scripts" <<'PY'
import math, os, sys
work = sys.argv[1]
sys.path.insert(0, sys.argv[2])
import bench_fixture
t0 = 1700000000.0
gt = []
for k in range(150):
    a = 2 * math.pi * k / 75
    gt.append((t0 + k / 15.0, 3.0 + math.cos(a), 2.5 + math.sin(a), 0.09))
for name in ("merged", "plain"):
    bench_fixture.write_render(work, name, gt)
def sim(p, s, yaw, tr):
    c, n = math.cos(yaw), math.sin(yaw)
    x, y, z = p[1] - 3.0, p[2] - 2.5, p[3]
    return (p[0], s * (c * x - n * y) + tr[0], s * (n * x + c * y) + tr[1], s * z + tr[2])
A = (0.5, 0.3, (1.0, -2.0, 0.5))
B = (2.0, -1.2, (-3.0, 0.0, 1.0))
with open(work + "/runs/merged.tum", "w") as f:
    f.write("# timestamp tx ty tz qx qy qz qw (camera in the map frame, TUM)\n# map 0\n")
    for p in gt[3:60]:
        f.write("%.9f %.9f %.9f %.9f 0 0 0 1\n" % sim(p, *A))
    f.write("# map 1\n")
    for p in gt[70:90]:
        f.write("%.9f %.9f %.9f %.9f 0 0 0 1\n" % sim(p, *B))
    f.write("# map 0\n")
    for p in gt[90:150]:
        f.write("%.9f %.9f %.9f %.9f 0 0 0 1\n" % sim(p, *A))
with open(work + "/runs/merged.frames.csv", "w") as f:
    f.write("#timestamp_ns,sequence,state,map_id,loops,merges\n")
    for k, p in enumerate(gt):
        state = "initializing" if k < 3 else "lost" if 60 <= k < 70 else "relocalized" if k == 100 else "tracking"
        f.write("%d,%d,%s,%d,%d,%d\n" % (round(p[0] * 1e9), k, state, 1 if 70 <= k < 90 else 0,
                                         1 if k >= 120 else 0, 1 if k == 90 else 0))
with open(work + "/runs/merged.log", "w") as f:
    # The frame log's columns come first.
    f.write("ale-slamd: loop closed at 1700000008.00 s: x\nale-slamd: frames 150 tracked 147 loops 7 merges 7\n")
with open(work + "/runs/plain.tum", "w") as f:
    f.write("# map 0\n")
    for p in gt:
        f.write("%.9f %.9f %.9f %.9f 0 0 0 1\n" % sim(p, *B))
with open(work + "/runs/plain.frames.csv", "w") as f:
    f.write("#timestamp_ns,sequence,state,map_id\n")
    for k, p in enumerate(gt):
        f.write("%d,%d,tracking,0\n" % (round(p[0] * 1e9), k))
with open(work + "/runs/plain.log", "w") as f:
    f.write("status: merges: 1\nale-slamd: frames 150 tracked 150 resets 0 loops_closed 3 loops_refused 1 merges 2 "
            "merges_refused 5 commands 0\n")
os.makedirs(work + "/renders/lines/mav0/cam0")
for f in ("groundtruth.txt", "mav0/cam0/data.csv"):
    os.link(work + "/renders/plain/" + f, work + "/renders/lines/" + f)
for f in ("tum", "frames.csv"):
    os.link(work + "/runs/plain." + f, work + "/runs/lines." + f)
with open(work + "/runs/lines.log", "w") as f:
    f.write("ale-slamd: loop closed at 1700000004.00 s: the place of 1700000000.50 s seen again\n"
            "ale-slamd: loop refused at 1700000006.00 s: it moves the keyframe too far\n"
            "ale-slamd: loop refused at 1700000006.50 s: it moves the keyframe too far\n"
            "ale-slamd: loop closed at 1700000008.00 s: the place of 1700000003.50 s seen again\n"
            "ale-slamd: frames 150 tracked 150 resets 0\n")
os.makedirs(work + "/renders/daemon/mav0/cam0")
for f in ("groundtruth.txt", "mav0/cam0/data.csv"):
    os.link(work + "/renders/plain/" + f, work + "/renders/daemon/" + f)
os.link(work + "/runs/plain.tum", work + "/runs/daemon.tum")
with open(work + "/runs/daemon.frames.csv", "w") as f:
    f.write("#timestamp_ns,sequence,state,map_id,loops,loop_ms,merges,merges_refused\n")
    for k, p in enumerate(gt):
        f.write("%d,%d,tracking,0,%d,0.100,%d,%d\n" % (round(p[0] * 1e9), k, 1 if k >= 40 else 0,
                                                     (k >= 90) + (k >= 120), min(k // 30, 4)))
with open(work + "/runs/daemon.log", "w") as f:
    f.write("ale-slamd: frames 150 tracked 150 resets 0 loops_closed 7 loops_refused 0 merges 9 merges_refused 0\n")
PY
out=$(python3 "$src/scripts/loop-bench-eval.py" --eval "$ale_eval" --renders "$work/renders" --runs "$work/runs" \
      "merged|blackout:3.5,0.5" "plain|-" "lines|-" "daemon|-")
echo "$out"
fail=0
check() { if [ "$(echo $2)" != "$3" ]; then echo "FAIL: $1 is '$(echo $2)', expected '$3'"; fail=1; fi; }
# 149 chords of 2 sin(pi/75) m: 12.48 m.
path=$(python3 -c 'import math; print("%.1f" % (149 * 2 * math.sin(math.pi / 75)))')
row=$(grep '^| merged |' <<<"$out")
IFS='|' read -r _ name path_m frames posed resets maps reloc loops refused merges ate ate_pct share map_cm map_pct back same note <<<"$row"
check "path m" "$path_m" "$path"
check frames "$frames" 150
check "posed %" "$posed" 93.2      # 137 poses over the 147 frames from the first pose on
check resets "$resets" 2           # into map 1 and back into map 0
check maps "$maps" 2               # map 0's two segments are one map
check reloc "$reloc" 1
check loops "$loops" 1             # a running count: its last value
check merges "$merges" 1           # a count per frame: summed
check "map share %" "$share" 85    # map 0: 117 of 137 poses
check "map cm" "$map_cm" 0.00      # its two segments fit one similarity exactly
check "map %" "$map_pct" 0.000
check "back s" "$back" 0.67        # light back at 4.0 s, first pose at frame 70 (4.667 s)
check "same map" "$same" no
# As one map, maps 0 and 1 do not fit one similarity: far from zero.
awk -v a="$(echo $ate)" 'BEGIN { exit !(a > 10.0) }' || { echo "FAIL: ATE as one map is $ate cm"; fail=1; }
row=$(grep '^| plain |' <<<"$out")
IFS='|' read -r _ name path_m frames posed resets maps reloc loops refused merges ate ate_pct share map_cm map_pct back same note <<<"$row"
check "plain: posed %" "$posed" 100.0
check "plain: resets" "$resets" 0
check "plain: maps" "$maps" 1
check "plain: loops" "$loops" 3    # the log's last `loops_closed N`
check "plain: merges" "$merges" 2  # the log's last `merges N`
check "plain: ATE cm" "$ate" 0.00
check "plain: map share %" "$share" 100
check "plain: note" "$note" ""     # one map: the same figure as ale-eval's
check "plain: refused" "$refused" "-"
# Route `lines`: the log's `loop closed at` and `loop refused at` lines, no counts.
row=$(grep '^| lines |' <<<"$out")
IFS='|' read -r _ name path_m frames posed resets maps reloc loops refused merges rest <<<"$row"
check "lines: loops" "$loops" 2
check "lines: refused" "$refused" 2
check "lines: merges" "$merges" "-"
# Route `daemon`: the frame log's running counts, their last values.
row=$(grep '^| daemon |' <<<"$out")
IFS='|' read -r _ name path_m frames posed resets maps reloc loops refused merges rest <<<"$row"
check "daemon: loops" "$loops" 1
check "daemon: merges" "$merges" 2
exit $fail
