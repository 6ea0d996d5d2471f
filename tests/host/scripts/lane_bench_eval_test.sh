#!/usr/bin/env bash
# scripts/lane-bench-eval.py on made-up runs whose answers are known: a ground truth of 100 frames
# on the floor, 2 cm a frame along x (frames 0-47), then along y (48-99): a 1.98 m path. An
# estimate that is the ground truth under a similarity has no error; one whose height is off by
# +d, -d, -d, +d in every four frames (on each leg it sums to zero against a constant and against
# the frame index, so against x and y) keeps the rotation and translation of the best similarity;
# only its scale s = G / (G + n d^2) (G: the ground truth's spread about its mean, n frames) takes
# up a little, and the ATE is sqrt(((1 - s)^2 G + s^2 n d^2) / n). Runs: `exact` (the similarity), `off5` (d = 5 cm), `none` (never initialised: no pose),
# `lost` (no trajectory file); baseline runs: `exact` with d = 2 cm, `off5` the same as now.
#   lane_bench_eval_test.sh SOURCE_DIR ALE_EVAL
set -euo pipefail
src=$1
ale_eval=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/runs" "$work/base"
python3 - "$work" "$src/tests/host/scripts" <<'PY'
import math, os, sys
work = sys.argv[1]
sys.path.insert(0, sys.argv[2])
import bench_fixture
t0 = 1700000000.0
gt = [(t0 + k / 15.0, 1.0 + 0.02 * min(k, 47), 2.0 + 0.02 * max(k - 47, 0), 0.09) for k in range(100)]
pattern = [1, -1, -1, 1]
def est(d, s=1.0, yaw=0.0, tr=(0.0, 0.0, 0.0)):
    c, n = math.cos(yaw), math.sin(yaw)
    out = []
    for k, (t, x, y, z) in enumerate(gt):
        z = z + d * pattern[k % 4]
        out.append((t, s * (c * x - n * y) + tr[0], s * (n * x + c * y) + tr[1], s * z + tr[2]))
    return out
def write_run(folder, name, poses):
    with open("%s/%s/%s.tum" % (work, folder, name), "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw (camera in the map frame, TUM)\n# map 0\n")
        for p in poses:
            f.write("%.9f %.9f %.9f %.9f 0 0 0 1\n" % p)
    with open("%s/%s/%s.frames.csv" % (work, folder, name), "w") as f:
        f.write("#timestamp_ns,sequence,state,map_id\n")
        for k, p in enumerate(gt):
            f.write("%d,%d,tracking,0\n" % (round(p[0] * 1e9), k))
    open("%s/%s/%s.log" % (work, folder, name), "w").write("ale-slamd: frames 100 tracked 100 resets 0\n")
for name in ("exact", "off5", "none", "lost"):
    bench_fixture.write_render(work, name, gt)
write_run("runs", "exact", est(0.0, 2.5, 0.7, (3.0, -1.0, 0.5)))
write_run("runs", "off5", est(0.05))
for name in ("none", "lost"):
    with open(work + "/runs/%s.frames.csv" % name, "w") as f:
        f.write("#timestamp_ns,sequence,state,map_id\n")
        for k, p in enumerate(gt):
            f.write("%d,%d,initializing,0\n" % (round(p[0] * 1e9), k))
open(work + "/runs/none.tum", "w").write("# timestamp tx ty tz qx qy qz qw (camera in the map frame, TUM)\n")
write_run("base", "exact", est(0.02))
write_run("base", "off5", est(0.05))
n = len(gt)
mean = [sum(p[i] for p in gt) / n for i in (1, 2, 3)]
G = sum((p[i + 1] - mean[i]) ** 2 for p in gt for i in range(3))
path = sum(math.dist(a[1:], b[1:]) for a, b in zip(gt, gt[1:]))
def ate(d):
    s = G / (G + n * d * d)
    return math.sqrt(((1 - s) ** 2 * G + s * s * n * d * d) / n)
with open(work + "/expected", "w") as f:
    f.write("%.2f %.3f %.3f %.2f %.3f %.3f\n" % (
        100 * ate(0.05), 100 * ate(0.05) / path, 100 * ate(0.02) / path, path, 50 * ate(0.05) / path,
        (100 * ate(0.02) / path + 100 * ate(0.05) / path) / 2))
PY
read -r off5_cm off5_pct exact_base path half base_mean < "$work/expected"
echo "expected: off5 $off5_cm cm, $off5_pct %; exact's baseline $exact_base %; path $path m"
set +e
out=$(python3 "$src/scripts/lane-bench-eval.py" --eval "$ale_eval" --renders "$work/renders" --runs "$work/runs" \
      --baseline "$work/base" "exact|-" "off5|-" "none|-" "lost|-")
status=$?
set -e
echo "$out"
fail=0
check() { if [ "$(echo $2)" != "$3" ]; then echo "FAIL: $1 is '$(echo $2)', expected '$3'"; fail=1; fi; }
check "exit status (a route without an ATE)" "$status" 1
row=$(grep '^| exact |' <<<"$out")
IFS='|' read -r _ name path_m frames posed resets maps reloc loops refused merges ate ate_pct base ratio note <<<"$row"
check "exact: ATE cm" "$ate" 0.00
check "exact: ATE %" "$ate_pct" 0.000
check "exact: base %" "$base" "$exact_base"
check "exact: ratio" "$ratio" 0.00
row=$(grep '^| off5 |' <<<"$out")
IFS='|' read -r _ name path_m frames posed resets maps reloc loops refused merges ate ate_pct base ratio note <<<"$row"
check "off5: ATE cm" "$ate" "$off5_cm"
check "off5: ATE %" "$ate_pct" "$off5_pct"
check "off5: ratio" "$ratio" 1.00
check "off5: path m" "$path_m" 2.0
row=$(grep '^| none |' <<<"$out")
IFS='|' read -r _ name path_m frames posed resets maps reloc loops refused merges ate ate_pct base ratio note <<<"$row"
check "none: ATE %" "$ate_pct" "-"
check "none: note" "$note" "no pose"
row=$(grep '^| lost |' <<<"$out")
IFS='|' read -r _ name path_m frames posed resets maps reloc loops refused merges ate ate_pct base ratio note <<<"$row"
check "lost: note" "$note" "no trajectory file"
check summary "$(grep '^ATE % over' <<<"$out")" "ATE % over 2 routes: mean $half, median $half, worst $off5_pct (off5)"
check "against" "$(grep '^against' <<<"$out" | sed 's/^against [^ ]* //')" \
  "over 2 routes: better 1, worse 0, even 1 (sign test p = 1.000); mean $half against $base_mean, median $half against $base_mean"
check "missing" "$(grep '^no ATE' <<<"$out")" "no ATE for: none, lost"
[ $fail -eq 0 ] && echo "lane-bench table: all checks passed"
exit $fail
