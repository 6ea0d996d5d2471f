#!/usr/bin/env bash
# scripts/experiments-eval.py on made-up runs whose answers are known (no rendering, no replay):
# seven sequences, each with an `off` and an `ale` run. The ground truth is a loop; a run is the
# ground truth under a similarity (exact after a Sim(3) alignment) or with a wobble added (not).
# Dark (six sequences): ale exact, off wobbly -> ale wins 6 of 6, two-sided sign test p = 2/64;
# ale's frame logs hold the inliers 5, 20, 30, 9, 10 over and over -> VIA (frames with >= 10)
# = 20.0; off's hold 9 on every frame -> no VIA. Normal (one): off exact, ale wobbly -> over all
# seven ale wins 6, loses 1, p = 2 x 8/128 = 0.125, and is more than 10 % worse on 1. One off run
# loses track for 10 frames (state lost) and starts a new map: 1 loss, 1 reset.
# Also the sign test itself on known splits.
#   experiments_eval_test.sh SOURCE_DIR ALE_EVAL
set -euo pipefail
src=$1
ale_eval=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 - "$work" <<'PY'
import math, os, sys
work = sys.argv[1]
t0 = 1700000000.0
header = ("#timestamp_ns,sequence,state,brightness,mean,sigma,gamma,clip,negative,features,inliers,frame_time_ms,"
          "map_id,keyframes,landmarks,frontend_ms,tracking_ms,mapping_ms,place_ms\n")
def loop(k):
    a = 0.07 * k
    return (t0 + k / 15.0, 2.0 + 1.5 * math.cos(a), 2.0 + 1.0 * math.sin(a), 0.09 + 0.02 * math.sin(2 * a))
def write(name, mode, exact, lost=False, cycle=True):
    gt = [loop(k) for k in range(100)]
    os.makedirs(os.path.join(work, "renders", name), exist_ok=True)
    with open(os.path.join(work, "renders", name, "groundtruth.txt"), "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        for t, x, y, z in gt:
            f.write("%.9f %.9f %.9f %.9f 0 0 0 1\n" % (t, x, y, z))
    d = os.path.join(work, "runs", name)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, mode + ".tum"), "w") as f:
        f.write("# map 0\n")
        for k, (t, x, y, z) in enumerate(gt[5:], 5):
            if lost and 50 <= k < 60:
                continue
            if lost and k == 60:
                f.write("# map 1\n")
            wob = 0.0 if exact else 0.05 * math.sin(1.3 * k)
            # a similarity: scale 0.5, shifted
            f.write("%.9f %.9f %.9f %.9f 0 0 0 1\n" % (t, 0.5 * x + 1.0 + wob, 0.5 * y - 2.0, 0.5 * z + wob))
    with open(os.path.join(d, mode + ".csv"), "w") as f:
        f.write(header)
        for k, (t, *_rest) in enumerate(gt):
            state = "initializing" if k < 5 else ("lost" if lost and 50 <= k < 60 else "tracking")
            inl = [5, 20, 30, 9, 10][k % 5] if cycle else 9
            f.write("%d,%d,%s,dark,40.0,10.0,1.0,0.0,0,500,%d,5.0,%d,5,100,1.0,1.0,1.0,0.0\n" % (
                round(t * 1e9), k, state, inl, 1 if lost and k >= 60 else 0))
for i in range(6):
    write("var.dark.s%d" % i, "ale", True)
    write("var.dark.s%d" % i, "off", False, lost=(i == 0), cycle=False)
write("var.normal.s9", "ale", False)
write("var.normal.s9", "off", True)
PY
names=(var.dark.s0 var.dark.s1 var.dark.s2 var.dark.s3 var.dark.s4 var.dark.s5 var.normal.s9)
python3 "$src/scripts/experiments-eval.py" --eval "$ale_eval" --out "$work" --results "$work/results.md" \
  --modes "off ale" --command "test" --build "test" "${names[@]}"
fail=0
expect() {
  if ! grep -qF -- "$1" "$work/results.md"; then
    echo "FAIL: results.md lacks: $1" >&2
    fail=1
  fi
}
# ale against off, per condition and over all: wins/losses/ties, p, runs more than 10 % worse
expect "| dark | 6 | 6/0/0, p 0.031, 0 |"
expect "| normal | 1 | 0/1/0, p 1, 1 |"
expect "| all | 7 | 6/1/0, p 0.12, 1 |"
# dark, per mode: 6 runs with an ATE; off: tracked 85 of 95 on one run -> mean 98.2 %, 5 of 6
# fully tracked, 1 loss, 1 reset, no VIA; ale: VIA 20.0, all tracked
expect "| off | 6 | 6 |"
grep -F "| off | 6 | 6 |" "$work/results.md" | head -1 | grep -qF "| 98.2 | 5/6 | 1 | 1 | - | 500 |" ||
  { echo "FAIL: dark off row: $(grep -F '| off | 6 | 6 |' "$work/results.md" | head -1)" >&2; fail=1; }
grep -F "| ale | 6 | 6 |" "$work/results.md" | head -1 | grep -qF "| 100.0 | 6/6 | 0 | 0 | 20.0 | 500 |" ||
  { echo "FAIL: dark ale row: $(grep -F '| ale | 6 | 6 |' "$work/results.md" | head -1)" >&2; fail=1; }
# the exact runs' ATE is 0.00 cm
grep -F "| ale | 6 | 6 |" "$work/results.md" | head -1 | grep -qF "| ale | 6 | 6 | 0.00 | 0.00 |" ||
  { echo "FAIL: ale's exact runs do not score 0.00 cm" >&2; fail=1; }
expect "Sequences where ale's VIA is below off's: 0 of 7."
# the sign test on known splits; VIA on a known list
python3 - "$src/scripts/experiments-eval.py" <<'PY' || fail=1
import importlib.util, sys
spec = importlib.util.spec_from_file_location("ee", sys.argv[1])
ee = importlib.util.module_from_spec(spec)
spec.loader.exec_module(ee)
cases = [((6, 0), 2 / 64), ((0, 6), 2 / 64), ((5, 5), 1.0), ((1, 9), 2 * 11 / 1024), ((0, 0), 1.0), ((20, 5), 2 * sum(
    __import__("math").comb(25, k) for k in range(6)) / 2 ** 25)]
for (w, l), p in cases:
    got = ee.sign_test(w, l)
    if abs(got - p) > 1e-12:
        sys.exit("FAIL: sign_test(%d, %d) = %r, expected %r" % (w, l, got, p))
if ee.via([5, 20, 30, 9, 10]) != (20.0, 3) or ee.via([9, 3]) != (None, 0):
    sys.exit("FAIL: via")
if [ee.compare(1, 2), ee.compare(2, 1), ee.compare(None, 1), ee.compare(1, None), ee.compare(None, None)] != [1, -1, -1, 1, 0]:
    sys.exit("FAIL: compare")
PY
[ $fail -eq 0 ] || { sed -n '1,200p' "$work/results.md" >&2; exit 1; }
echo "experiments_eval_test: ok"
