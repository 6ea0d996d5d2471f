#!/usr/bin/env python3
"""The table of scripts/odometry-bench.sh: one row per sequence, odometry alone, vision alone, fused.

usage: odometry-bench-eval.py --eval ALE_EVAL --renders DIR --runs DIR NAME|EVENT ...

For each NAME: DIR/renders/NAME (groundtruth.txt, mav0/, lighting.csv) and DIR/runs/NAME.vision.*
(ale-slamd --no-odometry) and NAME.fused.* (with odometry): .tum, .frames.csv. EVENT is - or
blackout:START,DURATION. Columns:
  path m       length of the ground-truth path (all frames)
  odo cm / %   the odometry alone (ale-eval odometry --times frames), ATE after an SE(3) alignment:
               cm and % of the path
  vis Sim3 %   the camera alone, ATE after a Sim(3) alignment, % of the path
  vis posed %  frames with a pose / all frames (camera alone)
  fused cm / % fused, ATE after an SE(3) alignment (metric: the map in metres)
  fused Sim3 % fused, ATE after a Sim(3) alignment
  scale err %  |1 - s| x 100, s the scale of that Sim(3) alignment
  posed %      frames with a pose / all frames (fused)
  resets       map changes in the fused run's frame log
  reloc        frames the fused run relocalised
  fused/odo    fused metric ATE / odometry metric ATE (issue 34: <= 0.7)
  vs vision    fused Sim(3) ATE / vision Sim(3) ATE (issue 34: < 1)
A blackout row's fused run holds the odometry-propagated poses of the dark frames too
(daemon.trajectory_poses=online); below the table: its posed share and the position error of the
last dark frame's pose (lighting.csv's last `blackout` row) after the SE(3) alignment of the
whole run. Exit status 1 when a figure could not be measured.
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


def figures(ale_eval, args):
    """ale-eval's `key value` lines as a dict, or raises with its complaint."""
    proc = subprocess.run([ale_eval] + args + ["--print", "figures"], capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(" ".join((proc.stdout + proc.stderr).strip().splitlines()[:1]))
    out = {}
    for line in proc.stdout.splitlines():
        key, _, value = line.partition(" ")
        out[key] = value
    return out


def ate(ale_eval, gt, est, align, extra=()):
    f = figures(ale_eval, ["ate", "--gt", gt, "--est", est, "--align", align] + list(extra))
    return f


def path_length(gt):
    pts = [gt[k] for k in sorted(gt)]
    return sum(pbe.dist(a, b) for a, b in zip(pts, pts[1:]))


def count_poses(tum):
    with open(tum) as f:
        return sum(1 for line in f if line.strip() and not line.startswith("#"))


def last_dark_time(lighting_csv):
    last = None
    with open(lighting_csv) as f:
        for line in f:
            v = line.strip().split(",")
            if len(v) > 1 and v[1] == "blackout":
                last = int(v[0]) * 1e-9
    return last


def row(ale_eval, renders, runs, name, event):
    r = {"name": name, "notes": []}
    seq = os.path.join(renders, name)
    gt_path = os.path.join(seq, "groundtruth.txt")
    gt = pbe.read_gt(gt_path)
    r["path"] = path_length(gt)
    n_frames = len(gt)
    run = os.path.join(runs, name)
    try:
        odo = run + ".odometry.tum"
        subprocess.run([ale_eval, "odometry", "--dataset", seq, "--out", odo, "--times", "frames"], check=True,
                       capture_output=True, text=True)
        r["odo"] = float(ate(ale_eval, gt_path, odo, "se3")["ate_rmse"])
    except (RuntimeError, subprocess.CalledProcessError) as e:
        r["notes"].append("odometry: %s" % (getattr(e, "stderr", "") or e).strip())
    for mode in ("vision", "fused"):
        tum = run + "." + mode + ".tum"
        if not os.path.exists(run + "." + mode + ".frames.csv"):
            r["notes"].append("no %s replay" % mode)
            continue
        r[mode + "_posed"] = 100.0 * count_poses(tum) / n_frames
        try:
            f = ate(ale_eval, gt_path, tum, "sim3")
            r[mode + "_sim3"] = float(f["ate_rmse"])
            r[mode + "_scale"] = float(f["scale"])
            if mode == "fused":
                r["fused_se3"] = float(ate(ale_eval, gt_path, tum, "se3")["ate_rmse"])
        except (RuntimeError, KeyError) as e:
            r["notes"].append("%s: %s" % (mode, e))
        if mode == "fused":
            log = pbe.read_frame_log(run + ".fused.frames.csv")
            ids = [x.get("map_id", "") for x in log]
            r["resets"] = sum(1 for a, b in zip(ids, ids[1:]) if a != b)
            r["reloc"] = sum(1 for x in log if x.get("state") == "relocalized")
            if event.startswith("blackout:"):
                t = last_dark_time(os.path.join(seq, "lighting.csv"))
                if t is None:
                    r["notes"].append("no blackout row in lighting.csv")
                else:
                    try:
                        f = ate(ale_eval, gt_path, tum, "se3", ["--at-time", "%.9f" % t])
                        r["dark_t"] = float(f["at_time_s"]) - int(open(
                            os.path.join(seq, "mav0", "cam0", "data.csv")).readlines()[1].split(",")[0]) * 1e-9
                        r["dark_err"] = float(f["at_time_error_m"])
                    except RuntimeError as e:
                        r["notes"].append("last dark frame: %s" % e)
    return r


def pct(r, key):
    return None if key not in r or not r.get("path") else 100.0 * r[key] / r["path"]


def ratio(a, b):
    return None if a is None or b is None or b == 0 else a / b


def cm(v):
    return None if v is None else 100.0 * v


def main(argv):
    cli = pbe.parse_cli(argv, __doc__)
    if cli is None:
        return 2
    args, rest = cli
    fmt = pbe.fmt
    print("| sequence | path m | odo cm | odo % | vis Sim3 % | vis posed % | fused cm | fused % | fused Sim3 % | "
          "scale err % | posed % | resets | reloc | fused/odo | vs vision | note |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    blackouts = []
    missing = False
    for item in rest:
        name, _, event = item.partition("|")
        r = row(args["--eval"], args["--renders"], args["--runs"], name, event or "-")
        f_o = ratio(r.get("fused_se3"), r.get("odo"))
        f_v = ratio(r.get("fused_sim3"), r.get("vision_sim3"))
        if f_o is None or f_v is None:
            missing = True
        scale_err = None if "fused_scale" not in r else 100.0 * abs(1.0 - r["fused_scale"])
        print("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            name, fmt(r.get("path"), ".1f"), fmt(cm(r.get("odo")), ".1f"), fmt(pct(r, "odo"), ".2f"),
            fmt(pct(r, "vision_sim3"), ".2f"), fmt(r.get("vision_posed"), ".1f"), fmt(cm(r.get("fused_se3")), ".1f"),
            fmt(pct(r, "fused_se3"), ".3f"), fmt(pct(r, "fused_sim3"), ".3f"), fmt(scale_err, ".2f"),
            fmt(r.get("fused_posed"), ".1f"), r.get("resets", "-"), r.get("reloc", "-"), fmt(f_o, ".2f"),
            fmt(f_v, ".2f"), "; ".join(r["notes"])))
        if event.startswith("blackout:"):
            blackouts.append((name, event, r))
    for name, event, r in blackouts:
        print("\n%s (%s): fused posed %s %% of all frames; the last dark frame (%s s) is off by %s cm after the "
              "SE(3) alignment of the whole run" % (name, event, fmt(r.get("fused_posed"), ".1f"),
                                                    fmt(r.get("dark_t"), ".2f"), fmt(cm(r.get("dark_err")), ".1f")))
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
