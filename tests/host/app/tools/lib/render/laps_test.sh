#!/usr/bin/env bash
# ale-render --laps: the loop and the lanes driven twice at 32x24. The frames cover exactly two
# laps; the ground truth one lap after each pose of the first lap is that pose again (the loop's
# lap is not a whole number of frames: interpolated between the two frames around it); the wheel
# odometry without noise runs on over the laps, and one lap on it reads what it read a lap before.
#   laps_test.sh ALE_RENDER
set -euo pipefail
render=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
for route in "loop" "lanes --lanes 2 --lane-length 1"; do
  name=${route%% *}
  # shellcheck disable=SC2086  # the route's options are words
  if ! "$render" --out "$work/$name" --trajectory $route --laps 2 --fps 15 --width 32 --height 24 --supersample 1 \
       --odometry-noise none > "$work/$name.log" 2>&1; then
    cat "$work/$name.log"
    echo "FAIL: ale-render --trajectory $route --laps 2"
    fail=1
    continue
  fi
  cat "$work/$name.log"
  python3 - "$work/$name" "$work/$name.log" <<'PY' || fail=1
import bisect, math, re, sys
out, log = sys.argv[1], open(sys.argv[2]).read()
m = re.search(r"^laps: 2 of ([0-9.]+) s \(([0-9.]+) s\)", log, re.M)
if not m:
    sys.exit("FAIL: no 'laps: 2 of ...' line")
lap = float(m.group(1))
fps = 15.0
bad = []
gt = []
for line in open(out + "/groundtruth.txt"):
    if line.startswith("#") or not line.strip():
        continue
    v = [float(x) for x in line.split()]
    gt.append((v[0], v[1:4], v[4:8]))
frames = sum(1 for l in open(out + "/mav0/cam0/data.csv") if not l.startswith("#"))
expect = math.floor(2 * lap * fps + 1e-6) + 1
if frames != expect or len(gt) != frames:
    bad.append("%d frames, %d ground-truth poses, expected %d (2 laps of %.3f s at 15 fps)" % (frames, len(gt), expect, lap))
t0 = gt[0][0]
times = [g[0] - t0 for g in gt]

def view(q):
    x, y, z, w = q  # the camera's optical axis (its z) in the world
    return (2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y))

def at(t):
    """Ground truth at t (from the first frame): positions and viewing directions interpolated."""
    i = min(max(bisect.bisect_right(times, t), 1), len(times) - 1)
    w = (t - times[i - 1]) / (times[i] - times[i - 1])
    (_, pa, qa), (_, pb, qb) = gt[i - 1], gt[i]
    va, vb = view(qa), view(qb)
    p = [a + w * (b - a) for a, b in zip(pa, pb)]
    v = [a + w * (b - a) for a, b in zip(va, vb)]
    n = math.sqrt(sum(c * c for c in v))
    return p, [c / n for c in v]

worst_m = worst_deg = 0.0
for t, p, q in gt:
    t -= t0
    if t + lap > times[-1] + 1e-9:
        break
    p2, v2 = at(t + lap)
    v = view(q)
    worst_m = max(worst_m, math.dist(p, p2))
    worst_deg = max(worst_deg, math.degrees(math.acos(max(-1.0, min(1.0, sum(a * b for a, b in zip(v, v2)))))))
print("ground truth one lap on: worst %.2f mm, %.3f deg" % (1000 * worst_m, worst_deg))
# Within one 5 ms trajectory sample of motion (1.5 mm at 0.3 m/s): a lap's end falls between samples.
if worst_m > 0.002 or worst_deg > 0.5:
    bad.append("the second lap is not the first: %.2f mm, %.3f deg apart" % (1000 * worst_m, worst_deg))
# The wheel odometry (no noise): over both laps, no jump, and one lap on the same reading.
odo = [[float(x) for x in l.split(",")[:4]] for l in open(out + "/mav0/odometry0/data.csv") if not l.startswith("#")]
ot = [(o[0] - odo[0][0]) * 1e-9 for o in odo]
if ot[-1] < times[-1] - 0.05:
    bad.append("odometry ends at %.2f s, the frames at %.2f s" % (ot[-1], times[-1]))
steps = [math.hypot(b[1] - a[1], b[2] - a[2]) / (tb - ta) for a, b, ta, tb in zip(odo, odo[1:], ot, ot[1:])]
if max(steps) > 0.5:  # the base drives at 0.3 m/s, a little more on the loop's bends
    bad.append("odometry jumps: %.2f m/s" % max(steps))
worst_odo_m = worst_odo_deg = 0.0
for k, t in enumerate(ot):
    if t + lap > ot[-1]:
        break
    j = min(max(bisect.bisect_right(ot, t + lap), 1), len(ot) - 1)
    w = (t + lap - ot[j - 1]) / (ot[j] - ot[j - 1])
    a, b = odo[j - 1], odo[j]
    x, y = (a[c] + w * (b[c] - a[c]) for c in (1, 2))
    th = a[3] + w * math.remainder(b[3] - a[3], 2 * math.pi)
    worst_odo_m = max(worst_odo_m, math.hypot(x - odo[k][1], y - odo[k][2]))
    worst_odo_deg = max(worst_odo_deg, abs(math.degrees(math.remainder(th - odo[k][3], 2 * math.pi))))
print("odometry one lap on: worst %.2f mm, %.3f deg" % (1000 * worst_odo_m, worst_odo_deg))
# Plus the linear interpolation between odometry samples (20 ms) where a drive meets a turn.
if worst_odo_m > 0.003 or worst_odo_deg > 0.5:
    bad.append("the odometry of the second lap is not the first's: %.2f mm, %.3f deg apart" % (1000 * worst_odo_m, worst_odo_deg))
for b in bad:
    print("FAIL: " + b)
sys.exit(1 if bad else 0)
PY
done
exit $fail
