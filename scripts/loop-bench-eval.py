#!/usr/bin/env python3
"""The table of scripts/loop-bench.sh: one row per replayed route.

usage: loop-bench-eval.py --eval ALE_EVAL --renders DIR --runs DIR NAME|EVENT ...

Inputs as scripts/place-bench-eval.py's (whose row it extends): DIR/renders/NAME (groundtruth.txt,
mav0/cam0/data.csv, render.log) and DIR/runs/NAME.tum, NAME.frames.csv, NAME.log. Columns:
  path m     length of the ground-truth path of the whole run (all frames), metres
  frames     frames replayed
  posed %    poses written / frames from the first pose on (after initialisation)
  resets     map_id changes in the frame log (a merge back into an older map counts too)
  maps       maps holding a pose in the trajectory file ("# map N" lines; one map's segments
             count once)
  reloc      frames whose frame-log state is `relocalized`
  loops      loops closed, merges  maps merged: from frame-log columns named loops (or
  merges     loops_closed) and merges (or maps_merged), a running count (its last value) or a
             count per frame (summed); else the daemon's log's last `loops N` (or `loops_closed`,
             `loops closed`, with or without a colon) and `merges N`; else, for loops, its
             `loop closed at` lines; `-` when none says
  refused    the daemon's `loop refused at` lines (`-` when it has none)
  ATE cm, %  ale-eval ate --align sim3 over all poses of the run aligned as one: its ate_rmse in
             cm and in % of the ground-truth path of the posed frames (full precision: its
             summary line rounds both to two digits)
  map share  the map holding the most poses: its share of all poses, %
  map cm, %  that map aligned on its own (Sim(3)): RMS error, cm and % of the ground-truth path
             of its own poses
  back s     blackout: seconds from the light coming back to the first pose after it
  same map   whether that pose is in the map the run was in before the blackout
A run of one map must give ale-eval's figure for that map (checked; a note when not).
"""
import importlib.util
import math
import os
import re
import subprocess
import sys

_spec = importlib.util.spec_from_file_location(
    "place_bench_eval", os.path.join(os.path.dirname(os.path.abspath(__file__)), "place-bench-eval.py"))
pbe = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(pbe)

LOOP_COLUMNS = ("loops", "loops_closed")
MERGE_COLUMNS = ("merges", "maps_merged")
# The daemon's line for each loop it closes, and for each it refuses.
LOOP_LINE = re.compile(r"^ale-slamd: loop closed at ", re.M)
REFUSED_LINE = re.compile(r"^ale-slamd: loop refused at ", re.M)


def event_count(frames, names):
    """A count from the first frame-log column of `names` present: its last value when the column
    never decreases (a running count), else the sum of its values (a count per frame); None when
    no row has such a column."""
    for name in names:
        values = []
        for f in frames:
            v = f.get(name, "")
            try:
                values.append(int(float(v)))
            except ValueError:
                pass
        if values:
            if all(b >= a for a, b in zip(values, values[1:])):
                return values[-1]
            return sum(values)
    return None


def log_count(log_text, pattern):
    """The last number the daemon's log gives after `pattern` (`merges: 3`, or `merges 3` as in its
    closing summary `frames 794 tracked 788 ... resets 0`), or None."""
    found = re.findall(pattern + r"\s*[:=]?\s*(\d+)\b", log_text)
    return int(found[-1]) if found else None


def path_length(points):
    return sum(pbe.dist(a, b) for a, b in zip(points, points[1:]))


def longest_map(segs, gt):
    """(share of poses %, ATE cm, ATE % of its own path) of the map holding the most poses; its
    segments are pooled (one map's frame). None when no map has 3 poses with ground truth."""
    by_map = {}
    for label, poses in segs:
        by_map.setdefault(label, []).extend(poses)
    total = sum(len(p) for p in by_map.values())
    label = max(by_map, key=lambda k: len(by_map[k])) if by_map else None
    if label is None:
        return None
    pairs = pbe.pairs_of(sorted(by_map[label]), gt)
    if len(pairs) < 3:
        return None
    sim = pbe.sim3_align([p[0] for p in pairs], [p[1] for p in pairs])
    rmse = math.sqrt(sum(pbe.dist(pbe.apply(sim, e), g) ** 2 for e, g, _ in pairs) / len(pairs))
    path = path_length([p[1] for p in pairs])
    return 100.0 * len(by_map[label]) / total, 100.0 * rmse, (100.0 * rmse / path if path > 0 else None)


def precise_ate(ale_eval, renders, runs, name, r):
    """Sets r's ate_cm and ate_pct from ale-eval's ate_rmse and the ground-truth path of the posed
    frames; a note when ale-eval gives none."""
    gt_path = os.path.join(renders, name, "groundtruth.txt")
    est_path = os.path.join(runs, name + ".tum")
    if not os.path.exists(gt_path) or not os.path.exists(est_path):
        return
    poses = sorted(p for _, seg in pbe.read_tum_segments(est_path) for p in seg)
    if not poses:
        return
    proc = subprocess.run([ale_eval, "ate", "--gt", gt_path, "--est", est_path, "--align", "sim3"],
                          capture_output=True, text=True)
    figures = dict(line.split(None, 1) for line in proc.stdout.splitlines() if len(line.split()) == 2)
    path = path_length([g for _, g, _ in pbe.pairs_of(poses, pbe.read_gt(gt_path))])
    try:
        rmse = float(figures["ate_rmse"])
    except (KeyError, ValueError):
        r.pop("ate_cm", None)
        r.pop("ate_pct", None)
        r["note"] = "ale-eval: " + (proc.stdout + proc.stderr).strip().split("\n")[0]
        return
    r["ate_cm"] = 100.0 * rmse
    r["ate_pct"] = 100.0 * rmse / path if path > 0 else None


def row(ale_eval, renders, runs, name, event):
    out = pbe.row(ale_eval, renders, runs, name, event)
    precise_ate(ale_eval, renders, runs, name, out)
    gt_path = os.path.join(renders, name, "groundtruth.txt")
    if not os.path.exists(gt_path):
        out["note"] = "no render"
        return out
    gt = pbe.read_gt(gt_path)
    out["path_m"] = path_length([gt[k] for k in sorted(gt)])
    run = os.path.join(runs, name)
    if not os.path.exists(run + ".frames.csv"):
        return out
    frames = pbe.read_frame_log(run + ".frames.csv")
    try:
        with open(run + ".log") as f:
            log_text = f.read()
    except OSError:
        log_text = ""
    loops = event_count(frames, LOOP_COLUMNS)
    if loops is None:
        loops = log_count(log_text, r"\bloops(?:[ _]closed)?")
    if loops is None and LOOP_LINE.search(log_text):
        loops = len(LOOP_LINE.findall(log_text))
    out["loops"] = loops
    out["refused"] = len(REFUSED_LINE.findall(log_text)) if REFUSED_LINE.search(log_text) else None
    merges = event_count(frames, MERGE_COLUMNS)
    out["merges"] = merges if merges is not None else log_count(log_text, r"\bmerges")
    segs = pbe.read_tum_segments(run + ".tum")
    out["maps"] = len({label for label, _ in segs})
    best = longest_map(segs, gt)
    if best:
        out["map_share"], out["map_cm"], out["map_pct"] = best
        if out["maps"] == 1 and "ate_cm" in out and abs(out["map_cm"] - out["ate_cm"]) > 0.05 * out["ate_cm"] + 0.1:
            out["note"] = "alignment differs from ale-eval's (%.1f vs %.1f cm)" % (out["map_cm"], out["ate_cm"])
    return out


# The table's columns: header, the row's key, its format (None: a count or text, `-` when absent).
COLUMNS = [("route", "name", None), ("path m", "path_m", ".1f"), ("frames", "frames", None),
           ("posed %", "posed", ".1f"), ("resets", "resets", None), ("maps", "maps", None), ("reloc", "reloc", None),
           ("loops", "loops", None), ("refused", "refused", None), ("merges", "merges", None), ("ATE cm", "ate_cm", ".2f"),
           ("ATE %", "ate_pct", ".3f"), ("map share %", "map_share", ".0f"), ("map cm", "map_cm", ".2f"),
           ("map %", "map_pct", ".3f"), ("back s", "back_s", ".2f"), ("same map", "same", None),
           ("note", "note", None)]


def cell(r, key, spec):
    if spec:
        return pbe.fmt(r.get(key), spec)
    if key == "note":
        return r.get(key, "")
    return "-" if r.get(key) is None else str(r[key])


def main(argv):
    cli = pbe.parse_cli(argv, __doc__)
    if cli is None:
        return 2
    args, items = cli
    print("| " + " | ".join(c[0] for c in COLUMNS) + " |")
    print("|" + "---|" * len(COLUMNS))
    for item in items:
        name, _, event = item.partition("|")
        r = row(args["--eval"], args["--renders"], args["--runs"], name, event or "-")
        r["name"] = name
        print("| " + " | ".join(cell(r, key, spec) for _, key, spec in COLUMNS) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
