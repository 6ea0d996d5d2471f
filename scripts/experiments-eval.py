#!/usr/bin/env python3
"""The page of scripts/experiments.sh (docs/results.md): every run scored, then per light
condition and enhancement mode, per pair of modes, and beside the article's figures.

usage: experiments-eval.py --eval ALE_EVAL --out DIR --results FILE [--features ALE_FEATURES]
                           [--data DIR] [--command CMD] [--build B] [--modes "off he clahe gamma ale"]
                           ITEM...

ITEM is NAME (the dataset DIR/renders/NAME) or NAME|DATASET; NAME is GROUP.CONDITION.VARIANT
(groups five, var, euroc, real; the condition is the ale-render --light profile). Each run is
DIR/runs/NAME/MODE.{tum,csv} (ale-slamd --trajectory, --frame-log), scored against
DATASET/groundtruth.txt; its figures are kept in DIR/runs/NAME/MODE.json (redone when the run is
newer). Per run:
  ATE       ale-eval ate --align sim3, RMSE, over all poses of the file (after a reset the maps
            are aligned as one, so a reset shows in the ATE); cm and % of the ground-truth path
  RPE       ale-eval rpe --align sim3 --delta 15 --delta-unit frames (1 s at 15 fps), RMSE, cm
  tracked   frames in state tracking or relocalized / frames from the first tracked one on
  losses    transitions into `lost`; resets: changes of map_id
  VIA       valid inlier average (the article's): mean of the frame log's `inliers` (the
            tracker's pose inliers after the local map) over the frames with at least 10
  features  mean keypoints a frame (the frame log's `features`); frame ms: median frame time
Comparisons between two modes are paired by sequence: a run without an ATE (never initialised,
fewer than 3 poses) loses to one with; equal ATEs tie and are left out of the two-sided sign test.
Writes FILE and, beside it, FILE without .md as a folder with ale-eval reports of the five-light
loop (top view, error over time, frame log plots).
"""
import importlib.util
import json
import math
import os
import re
import statistics
import subprocess
import sys

_spec = importlib.util.spec_from_file_location(
    "odometry_bench_eval", os.path.join(os.path.dirname(os.path.abspath(__file__)), "odometry-bench-eval.py"))
obe = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(obe)
pbe = obe.pbe

LEVELS = ["bright", "normal_bright", "normal", "normal_dark", "dark"]
CHANGING = ["off_on", "sunlit", "dimming"]
CONDITIONS = LEVELS + CHANGING
# The two sets: the dark and changing light, and the normal and bright light.
DARK_CHANGING = ["normal_dark", "dark", "off_on", "sunlit", "dimming"]
NORMAL_BRIGHT = ["bright", "normal_bright", "normal"]
VIA_MIN_INLIERS = 10
RPE_DELTA_FRAMES = 15
CACHE_VERSION = 1  # of the figures kept in MODE.json: older ones are scored again


# ---------------------------------------------------------------------------------------------
# Statistics

def sign_test(wins, losses):
    """Two-sided exact sign test: the probability, with wins and losses equally likely, of a split
    at least as uneven as this one (ties are left out before). 1 with no decided pair."""
    n = wins + losses
    if n == 0:
        return 1.0
    k = min(wins, losses)
    tail = sum(math.comb(n, i) for i in range(k + 1)) / 2.0 ** n
    return min(1.0, 2.0 * tail)


def via(inliers):
    """(VIA, frames it averages): mean inliers over the frames with at least VIA_MIN_INLIERS."""
    valid = [v for v in inliers if v >= VIA_MIN_INLIERS]
    return (sum(valid) / len(valid) if valid else None), len(valid)


def compare(a, b):
    """Paired comparison of two runs' ATE (smaller is better, None is worst): 1 a wins, -1 b wins,
    0 a tie."""
    if a is None and b is None:
        return 0
    if a is None:
        return -1
    if b is None:
        return 1
    return (a < b) - (a > b)


def mean(values):
    v = [x for x in values if x is not None]
    return sum(v) / len(v) if v else None


def median(values):
    v = [x for x in values if x is not None]
    return statistics.median(v) if v else None


# ---------------------------------------------------------------------------------------------
# One run

def frame_log_figures(rows):
    """The figures of one frame log (pbe.read_frame_log's rows)."""
    states = [r["state"] for r in rows]
    posed = [s in ("tracking", "relocalized") for s in states]
    first = next((i for i, p in enumerate(posed) if p), None)
    out = {"frames": len(rows), "first_tracked": first}
    out["tracked_after"] = sum(posed[first:]) if first is not None else 0
    out["after_frames"] = len(rows) - first if first is not None else 0
    out["losses"] = sum(1 for a, b in zip(states, states[1:]) if b == "lost" and a != "lost")
    ids = [r.get("map_id", "") for r in rows]
    out["resets"] = sum(1 for a, b in zip(ids, ids[1:]) if a != b)
    out["via"], out["via_frames"] = via([int(r["inliers"]) for r in rows])
    feats = [int(r["features"]) for r in rows]
    out["features"] = sum(feats) / len(feats) if feats else None
    classes = {}
    for r in rows:
        classes[r["brightness"]] = classes.get(r["brightness"], 0) + 1
    out["classes"] = classes
    out["mean_grey"] = mean([float(r["mean"]) for r in rows])
    out["frame_ms"] = median([float(r["frame_time_ms"]) for r in rows])
    return out


def score_run(ale_eval, gt_path, run_prefix):
    """All figures of one run (run_prefix + .tum, .csv), from its files and ale-eval."""
    out = frame_log_figures(pbe.read_frame_log(run_prefix + ".csv"))
    out["path_m"] = obe.path_length(pbe.read_gt(gt_path))
    notes = []
    try:
        f = obe.figures(ale_eval, ["ate", "--gt", gt_path, "--est", run_prefix + ".tum", "--align", "sim3"])
        out["ate_m"] = float(f["ate_rmse"])
    except (RuntimeError, KeyError, ValueError) as e:
        out["ate_m"] = None
        notes.append("ATE: %s" % e)
    try:
        f = obe.figures(ale_eval, ["rpe", "--gt", gt_path, "--est", run_prefix + ".tum", "--align", "sim3",
                                   "--delta", str(RPE_DELTA_FRAMES), "--delta-unit", "frames"])
        out["rpe_m"] = float(f["rpe_trans_rmse"])
    except (RuntimeError, KeyError, ValueError) as e:
        out["rpe_m"] = None
        notes.append("RPE: %s" % e)
    out["notes"] = notes
    return out


def load_run(ale_eval, gt_path, run_prefix):
    """score_run, kept in run_prefix.json until the run's files are newer."""
    cache = run_prefix + ".json"
    newest = max(os.path.getmtime(run_prefix + ext) for ext in (".tum", ".csv"))
    if os.path.exists(cache) and os.path.getmtime(cache) >= newest:
        with open(cache) as f:
            r = json.load(f)
        if r.get("version") == CACHE_VERSION:
            return r
    r = score_run(ale_eval, gt_path, run_prefix)
    r["version"] = CACHE_VERSION
    with open(cache, "w") as f:
        json.dump(r, f)
    return r


# ---------------------------------------------------------------------------------------------
# The article's figures (spec section 8), read from the spec when it is there

def article_table1(spec_path):
    """{sequence (MH01, V101 ...): [ORB-SLAM3, HE, CLAHE, Gamma, ALE-vSLAM] in metres} from the
    spec's Table I, or {} without the spec."""
    table = {}
    try:
        with open(spec_path) as f:
            text = f.read()
    except OSError:
        return table
    for m in re.finditer(r"^\|\s*(MH0\d|V[12]0\d|mean)\s*\|([^\n]*)$", text, re.M):
        values = [v.strip() for v in m.group(2).split("|") if v.strip()]
        try:
            table[m.group(1)] = [float(v) for v in values[:5]]
        except ValueError:
            continue
    return table


def article_key(seq):
    """MH_01_easy -> MH01, V1_02_medium -> V102."""
    m = re.match(r"(MH|V\d)_(\d\d)", seq)
    return (m.group(1) + m.group(2)) if m else seq


# ---------------------------------------------------------------------------------------------
# The page

def fmt(v, spec=".2f"):
    return pbe.fmt(v, spec)


def cm(v):
    return None if v is None else 100.0 * v


def pct_of_path(r):
    return None if r.get("ate_m") is None or not r.get("path_m") else 100.0 * r["ate_m"] / r["path_m"]


def tracked_pct(r):
    return None if not r.get("after_frames") else 100.0 * r["tracked_after"] / r["after_frames"]


def pvalue(p):
    return "%.2g" % p if p >= 0.001 else "%.1e" % p


def bar(value, top, width=40):
    if value is None or top <= 0:
        return ""
    eighths = int(round(8 * width * value / top))
    return "\u2588" * (eighths // 8) + ("" if eighths % 8 == 0 else chr(0x2590 - eighths % 8))


class Page:
    def __init__(self, modes, runs):
        self.modes = modes
        self.runs = runs            # {(name, mode): figures}
        self.names = sorted({n for n, _ in runs})
        self.lines = []

    def w(self, line=""):
        self.lines.append(line)

    def table(self, header, rows):
        self.w("| " + " | ".join(header) + " |")
        self.w("|" + "---|" * len(header))
        for r in rows:
            self.w("| " + " | ".join(str(c) for c in r) + " |")
        self.w()

    def names_in(self, conditions):
        """The rendered sequences of these conditions (the real ones have their own table)."""
        return [n for n in self.names if cond_of(n) in conditions and group_of(n) != "real"]

    def get(self, name, mode):
        return self.runs.get((name, mode))

    def run_rows(self, names, cell, label=lambda n: n.split(".", 2)[2]):
        """One row per sequence: its label, then cell(figures) per mode ("-" without a run)."""
        return [[label(n)] + ["-" if self.get(n, m) is None else cell(self.get(n, m)) for m in self.modes]
                for n in names]

    def pair(self, names, a, b):
        """(wins of a, losses, ties, runs where a is more than 10 % worse or has no ATE where b has)."""
        wins = losses = ties = worse10 = 0
        for n in names:
            ra, rb = self.get(n, a), self.get(n, b)
            if ra is None or rb is None:
                continue
            c = compare(ra["ate_m"], rb["ate_m"])
            wins += c > 0
            losses += c < 0
            ties += c == 0
            if rb["ate_m"] is not None and (ra["ate_m"] is None or ra["ate_m"] > 1.1 * rb["ate_m"]):
                worse10 += 1
        return wins, losses, ties, worse10


def group_of(name):
    return name.split(".")[0]


def cond_of(name):
    parts = name.split(".")
    return parts[1] if len(parts) > 2 else "?"


def common(page, names):
    """The sequences on which every mode's run has an ATE: the means over them compare like with like."""
    return [n for n in names if all(page.get(n, m) and page.get(n, m)["ate_m"] is not None for m in page.modes)]


def per_mode_rows(page, names):
    shared = common(page, names)
    rows = []
    for mode in page.modes:
        rs = [page.get(n, mode) for n in names if page.get(n, mode) is not None]
        if not rs:
            continue
        ates = [cm(r["ate_m"]) for r in rs]
        full = sum(1 for r in rs if r["after_frames"] and r["tracked_after"] == r["after_frames"])
        rows.append([mode, len(rs), sum(1 for a in ates if a is not None),
                     fmt(mean([cm(page.get(n, mode)["ate_m"]) for n in shared])), fmt(mean(ates)), fmt(median(ates)),
                     fmt(mean([pct_of_path(r) for r in rs])), fmt(median([pct_of_path(r) for r in rs])),
                     fmt(mean([cm(r["rpe_m"]) for r in rs])), fmt(mean([tracked_pct(r) for r in rs]), ".1f"),
                     "%d/%d" % (full, len(rs)), sum(r["losses"] for r in rs), sum(r["resets"] for r in rs),
                     fmt(mean([r["via"] for r in rs]), ".1f"), fmt(mean([r["features"] for r in rs]), ".0f"),
                     fmt(median([r["frame_ms"] for r in rs]), ".1f")])
    return rows


PER_MODE_HEADER = ["mode", "runs", "with ATE", "ATE mean cm, common", "ATE mean cm", "ATE median cm", "ATE mean %", "ATE median %",
                   "RPE mean cm", "tracked %", "all tracked", "losses", "resets", "VIA", "features", "frame ms"]


def write_page(page, args, extras):
    modes = page.modes
    w = page.w
    w("# Results: the article's experiments on our firmware")
    w()
    w("Generated by `%s` (scripts/experiments.sh, scripts/experiments-eval.py) on build `%s`; every "
      "figure below is measured by that run, nothing is copied in except the article's published "
      "figures (from ../shared/spec/ale-vslam.md, marked as the article's). Do not edit by hand." %
      (args["command"], args["build"]))
    w()
    counts = {}
    for n in page.names:
        counts[group_of(n)] = counts.get(group_of(n), 0) + 1
    w("Sequences: %d (%s), each replayed with `ale-slamd --replay DIR --no-odometry --set "
      "enhancement.mode=M` for M in %s: %d runs. Renders: `ale-render` at 15 fps, supersample 1; the "
      "five-light loop 320x240 20 s, the variants 320x240 12 s (loop, square, lanes with turns on the "
      "spot; rooms, texture seeds, sensor seeds and noise models spread over the conditions), the EuRoC "
      "flights 640x480 20 s from take-off. The firmware has no loop closing, so every run is without it, "
      "as the article ran its sweeper." % (
          len(page.names), ", ".join("%s %d" % (g, c) for g, c in sorted(counts.items())), ", ".join(modes),
          len(page.runs)))
    w()
    w("Determinism: %s." % extras.get("determinism", "not checked"))
    w()
    if extras.get("missing"):
        w("**Not replayed when this page was written** (left out of every table): %d runs: %s." % (
            len(extras["missing"]), ", ".join(extras["missing"])))
        w()
    w("Definitions (scripts/experiments-eval.py): ATE = RMSE after a Sim(3) alignment of all poses of the "
      "run (a reset's maps aligned as one), cm and %% of the ground-truth path; RPE = RMSE of the relative "
      "translation over %d frames after a Sim(3) alignment, cm; tracked = frames posed from the first "
      "posed frame on; all tracked = runs that pose every frame after initialisation; losses = "
      "transitions into lost; resets = new maps; VIA = mean tracking inliers over frames with at least "
      "%d (the frame log's `inliers`: the tracker's pose inliers after the local map); features = mean "
      "keypoints a frame; frame ms = median over runs of each run's median frame time (on a shared "
      "2-core host: compare within this page only). Means and medians are over the runs with a figure; "
      "`with ATE` counts them; `ATE mean cm, common` is the mean over the sequences on which every mode has "
      "an ATE (the same sequences for every mode)." % (RPE_DELTA_FRAMES, VIA_MIN_INLIERS))
    w()

    # The criteria of issue 35, as measured.
    w("## The issue's figures, as measured")
    w()
    criteria(page)

    w("## Per light condition and mode")
    w()
    for cond in CONDITIONS + ["?"]:
        names = page.names_in([cond])
        if not names:
            continue
        grey = mean([page.get(n, "ale")["mean_grey"] for n in names if page.get(n, "ale")])
        w("### %s (%d sequences, %d with an ATE in every mode, raw mean grey %s)" % (
            cond, len(names), len(common(page, names)), fmt(grey, ".0f")))
        w()
        page.table(PER_MODE_HEADER, per_mode_rows(page, names))
    for title, conds in (("dark and changing light (%s)" % ", ".join(DARK_CHANGING), DARK_CHANGING),
                         ("normal and bright light (%s)" % ", ".join(NORMAL_BRIGHT), NORMAL_BRIGHT)):
        names = page.names_in(conds)
        if names:
            w("### All of %s: %d sequences, %d with an ATE in every mode" % (
                title, len(names), len(common(page, names))))
            w()
            page.table(PER_MODE_HEADER, per_mode_rows(page, names))

    w("## ale against each mode, paired by sequence")
    w()
    w("Wins / losses / ties of ale's ATE against the other mode's on the same sequence; p: two-sided "
      "sign test over the decided pairs; >10 %: sequences where ale's ATE is more than 10 % above the "
      "other's (or ale has none where the other has).")
    w()
    if "ale" in modes:
        header = ["condition", "sequences"] + ["vs %s: W/L/T, p, >10 %%" % m for m in modes if m != "ale"]
        rows = []
        for cond in CONDITIONS + ["dark+changing", "normal+bright", "all"]:
            conds = {"dark+changing": DARK_CHANGING, "normal+bright": NORMAL_BRIGHT,
                     "all": CONDITIONS}.get(cond, [cond])
            names = page.names_in(conds)
            if not names:
                continue
            row = [cond, len(names)]
            for m in modes:
                if m == "ale":
                    continue
                wins, losses, ties, worse = page.pair(names, "ale", m)
                row.append("%d/%d/%d, p %s, %d" % (wins, losses, ties, pvalue(sign_test(wins, losses)), worse))
            rows.append(row)
        page.table(header, rows)
    w("Every pair of modes over all sequences (row mode's wins / losses against the column's, p):")
    w()
    names = page.names_in(CONDITIONS)
    rows = []
    for a in modes:
        row = [a]
        for b in modes:
            if a == b:
                row.append("-")
                continue
            wins, losses, _ties, _ = page.pair(names, a, b)
            row.append("%d/%d, p %s" % (wins, losses, pvalue(sign_test(wins, losses))))
        rows.append(row)
    page.table(["mode"] + modes, rows)

    five_light(page, args)
    euroc_tables(page, args)
    via_bars(page)
    feature_tables(page, extras)
    real_table(page)

    w("## Every run")
    w()
    w("<details><summary>ATE cm (tracked %, resets) per sequence and mode</summary>")
    w()
    page.table(["sequence"] + modes, page.run_rows(page.names, lambda r: "%s (%s, %d)" % (
        fmt(cm(r["ate_m"])), fmt(tracked_pct(r), ".0f"), r["resets"]), label=lambda n: n))
    w("</details>")
    w()


def criteria(page):
    w = page.w
    modes = page.modes
    if "ale" not in modes or "off" not in modes:
        w("(needs the modes ale and off)")
        w()
        return
    dc = page.names_in(DARK_CHANGING)
    nb = page.names_in(NORMAL_BRIGHT)
    for title, names in (("dark and changing light", dc), ("normal and bright light", nb)):
        if not names:
            continue
        pairs = [(page.get(n, "ale"), page.get(n, "off")) for n in names]
        pairs = [(a, o) for a, o in pairs if a and o and a["ate_m"] is not None and o["ate_m"] is not None]
        ma, mo = mean([cm(a["ate_m"]) for a, _ in pairs]), mean([cm(o["ate_m"]) for _, o in pairs])
        wins, losses, ties, _ = page.pair(names, "ale", "off")
        change = None if not mo else 100.0 * (ma - mo) / mo
        w("- %s, %d sequences (%d with an ATE in both): mean ATE ale %s cm, off %s cm (ale %s %%); ale wins "
          "%d, loses %d, ties %d, sign test p %s." % (
              title, len(names), len(pairs), fmt(ma), fmt(mo), fmt(change, "+.1f"), wins, losses, ties,
              pvalue(sign_test(wins, losses))))
    # ale against every other mode on each condition's mean over the common sequences
    behind = []
    for cond in CONDITIONS:
        names = page.names_in([cond])
        shared = common(page, names)
        if not shared or "ale" not in modes:
            continue
        means = {m: mean([cm(page.get(n, m)["ate_m"]) for n in shared]) for m in modes}
        unscored = {m: sum(1 for n in names if page.get(n, m) and page.get(n, m)["ate_m"] is None) for m in modes}
        better = sorted((m for m in modes if m != "ale" and means[m] < means["ale"]), key=lambda m: means[m])
        if better:
            behind.append("%s (%d common: ale %s cm; %s; runs without an ATE: %s)" % (
                cond, len(shared), fmt(means["ale"]), ", ".join("%s %s" % (m, fmt(means[m])) for m in better),
                ", ".join("%s %d" % (m, unscored[m]) for m in modes)))
    w("- Conditions where another mode has a lower mean ATE than ale over the sequences every mode scored: %s." %
      ("; ".join(behind) if behind else "none"))
    worst = []
    for m in modes:
        if m == "ale":
            continue
        _, _, _, worse = page.pair(page.names_in(CONDITIONS), "ale", m)
        worst.append("%s %d" % (m, worse))
    w("- Sequences where ale's ATE is more than 10 %% above the other mode's: %s (of %d)." % (
        ", ".join(worst), len(page.names_in(CONDITIONS))))
    five = [n for n in page.names if group_of(n) == "five"]
    untracked = []
    for n in five:
        for m in modes:
            r = page.get(n, m)
            if r and r["tracked_after"] < r["after_frames"] or (r and r["first_tracked"] is None):
                untracked.append("%s %s (%d of %d)" % (cond_of(n), m, r["tracked_after"], r["after_frames"]))
    w("- Five-light loop, runs that do not pose every frame after initialisation: %s." % (
        "; ".join(untracked) if untracked else "none"))
    lower = [n for n in page.names if page.get(n, "ale") and page.get(n, "off")
             and (page.get(n, "ale")["via"] or 0) < (page.get(n, "off")["via"] or 0)]
    w("- Sequences where ale's VIA is below off's: %d of %d%s." % (
        len(lower), sum(1 for n in page.names if page.get(n, "ale") and page.get(n, "off")),
        (" (" + ", ".join(lower[:12]) + (", ..." if len(lower) > 12 else "") + ")") if lower else ""))
    w()


def five_light(page, args):
    w = page.w
    names = [n for n in page.names if group_of(n) == "five"]
    if not names:
        return
    names.sort(key=lambda n: LEVELS.index(cond_of(n)) if cond_of(n) in LEVELS else 99)
    w("## The sweeper loop at the article's five light levels (its Fig. 10)")
    w()
    w("The loop in the living room, 20 s at 15 fps, 320x240, standard noise, sensor seed 1. Per mode: "
      "ATE cm, frames tracked after initialisation, resets, VIA; each links to its `ale-eval` report "
      "(top view of the aligned trajectory on the ground truth, error over time, and the frame log: "
      "brightness class, features, inliers, frame time, state).")
    w()
    rows = []
    for n in names:
        grey = page.get(n, "ale")["mean_grey"] if page.get(n, "ale") else None
        row = ["%s (grey %s)" % (cond_of(n), fmt(grey, ".0f"))]
        for m in page.modes:
            r = page.get(n, m)
            if r is None:
                row.append("-")
                continue
            cell = "%s cm, %d/%d, %d, VIA %s" % (fmt(cm(r["ate_m"])), r["tracked_after"], r["after_frames"],
                                                r["resets"], fmt(r["via"], ".0f"))
            link = r.get("report")
            row.append("[%s](%s)" % (cell, link) if link else cell)
        rows.append(row)
    page.table(["level"] + page.modes, rows)


def euroc_tables(page, args):
    w = page.w
    # in the article's order: MH_01 ... V2_02 (the variant starts with the flight's name)
    names = sorted((n for n in page.names if group_of(n) == "euroc"), key=lambda n: n.split(".", 2)[2])
    if not names:
        return
    art = article_table1(args["spec"])
    w("## EuRoC flights (the article's Table I and II)")
    w()
    w("Rendered along the nine EuRoC ground-truth trajectories of the article's Table I (20 s from "
      "take-off, 640x480, EuRoC's cam0 mounting, in a hall sized around the flight) with light like the "
      "real recordings; sensor seed 1 with the standard noise (other seeds, when rendered: small-pixel in "
      "the Vicon rooms, harsh in the machine halls). Ours: ATE in metres (Sim(3)); the article's columns: its Table I on "
      "the real sequences (ORB-SLAM3, HE, CLAHE, Gamma, ALE-vSLAM; %s). Renders are not the real "
      "recordings: compare the ranking of the modes, not the values." % (
          "from the spec" if art else "the spec was not found: not shown"))
    w()
    header = ["flight (light, noise)"] + ["%s m" % m for m in page.modes] + (
        ["article ORB-SLAM3", "HE", "CLAHE", "Gamma", "ALE-vSLAM"] if art else [])
    rows = []
    sums = {m: [] for m in page.modes}
    for n in names:
        variant = n.split(".", 2)[2]
        seq = variant.split("-")[0]
        row = ["%s (%s, %s)" % (seq, cond_of(n), variant.split("-", 1)[1])]
        for m in page.modes:
            r = page.get(n, m)
            v = None if r is None else r["ate_m"]
            sums[m].append(v)
            row.append(fmt(v, ".4f") + ("" if r is None or r["resets"] == 0 else " (%d resets)" % r["resets"]))
        if art:
            row += [fmt(v, ".4f") for v in art.get(article_key(seq), [None] * 5)] if variant.endswith("-s1") \
                else [""] * 5
        rows.append(row)
    mrow = ["mean (runs with an ATE)"] + [fmt(mean(sums[m]), ".4f") for m in page.modes]
    if art:
        mrow += [fmt(v, ".4f") for v in art.get("mean", [None] * 5)]
    rows.append(mrow)
    page.table(header, rows)
    w("RPE (Table II's measure; the article's RPE figures are not in the spec), cm over %d frames:" %
      RPE_DELTA_FRAMES)
    w()
    page.table(["flight"] + page.modes, page.run_rows(names, lambda r: fmt(cm(r["rpe_m"]))))


def via_bars(page):
    w = page.w
    w("## VIA per light condition (the article's Fig. 8)")
    w()
    w("Mean VIA over the condition's runs (the article: ORB-SLAM3 about 176-185, ALE-vSLAM 186-189 on "
      "real MH01, MH03, MH05, V102). Bars to scale within this chart.")
    w()
    entries = []
    for cond in CONDITIONS:
        names = page.names_in([cond])
        for m in page.modes:
            v = mean([page.get(n, m)["via"] for n in names if page.get(n, m)])
            if v is not None:
                entries.append((cond, m, v))
    if not entries:
        return
    top = max(v for _, _, v in entries)
    w("```")
    for cond, m, v in entries:
        w("%-14s %-6s %6.1f %s" % (cond, m, v, bar(v, top)))
    w("```")
    w()


def feature_tables(page, extras):
    w = page.w
    w("## Features per light level (the article's Table III)")
    w()
    w("Mean keypoints a frame (budget 1000) over the condition's runs, per mode; the last column: how "
      "ale graded the raw frames (extremely dark / dark / normal / bright, % of the frames):")
    w()
    rows = []
    classes = ["extremely_dark", "dark", "normal", "bright"]
    for cond in CONDITIONS:
        names = page.names_in([cond])
        if not names:
            continue
        graded = {c: 0 for c in classes}
        for n in names:
            r = page.get(n, "ale")
            for c in classes:
                graded[c] += r["classes"].get(c, 0) if r else 0
        total = sum(graded.values())
        rows.append([cond] + [fmt(mean([page.get(n, m)["features"] for n in names if page.get(n, m)]), ".0f")
                              for m in page.modes] +
                    [" / ".join("%.0f" % (100.0 * graded[c] / total) for c in classes) if total else "-"])
    page.table(["condition"] + page.modes + ["ale's grading %"], rows)
    if extras.get("article_frames"):
        w("Single real frames (`ale-features --article --data DIR`: EuRoC V1_01 normal, the same brightened "
          "by 65 %, the real EuRoC dark frame; modes baseline = off, clahe, ale):")
        w()
        page.table(["frame", "mode", "features", "per level"], extras["article_frames"])


def real_table(page):
    names = [n for n in page.names if group_of(n) == "real"]
    if not names:
        return
    w = page.w
    w("## Real sequences")
    w()
    w("TUM fr2_desk_20 (20 real frames, about 10 Hz; EuRoC V1_01 micro is left out: its camera does not "
      "move). ATE cm, tracked after initialisation, VIA:")
    w()
    page.table(["sequence"] + page.modes, page.run_rows(names, lambda r: "%s cm, %d/%d, VIA %s" % (
        fmt(cm(r["ate_m"])), r["tracked_after"], r["after_frames"], fmt(r["via"], ".0f"))))


def article_frames(features_bin, data):
    """Rows of `ale-features --article` (frame, mode, features, per level), or [] when it cannot run."""
    if not features_bin or not os.path.exists(features_bin) or not os.path.isdir(data):
        return []
    proc = subprocess.run([features_bin, "--article", "--data", data], capture_output=True, text=True)
    rows = []
    for line in proc.stdout.splitlines():
        m = re.match(r"(\S+) mode=(\S+) features=(\d+) levels=(\S+)", line)
        if m:
            rows.append([m.group(1), m.group(2), m.group(3), m.group(4)])
    return rows


def parse_args(argv):
    args = {"features": None, "data": "", "command": "scripts/experiments.sh", "build": "unknown",
            "modes": "off he clahe gamma ale"}
    items = []
    i = 1
    keys = ("--eval", "--features", "--data", "--out", "--results", "--command", "--build", "--modes")
    while i < len(argv):
        if argv[i] in keys and i + 1 < len(argv):
            args[argv[i][2:]] = argv[i + 1]
            i += 2
        elif argv[i].startswith("--"):
            return None
        else:
            items.append(argv[i])
            i += 1
    if not all(k in args for k in ("eval", "out", "results")) or not items:
        return None
    args["items"] = items
    args["modes"] = args["modes"].split()
    args["spec"] = os.path.join(args["data"] or ".", "..", "spec", "ale-vslam.md")
    return args


def main(argv):
    args = parse_args(argv)
    if args is None:
        sys.stderr.write(__doc__)
        return 2
    out = args["out"]
    results = args["results"]
    plots = results[:-3] if results.endswith(".md") else results + ".d"
    runs = {}
    missing = []
    for item in args["items"]:
        name, _, dataset = item.partition("|")
        dataset = dataset or os.path.join(out, "renders", name)
        gt = os.path.join(dataset, "groundtruth.txt")
        for mode in args["modes"]:
            prefix = os.path.join(out, "runs", name, mode)
            if not (os.path.exists(prefix + ".csv") and os.path.exists(prefix + ".tum")):
                missing.append("%s %s" % (name, mode))
                continue
            runs[(name, mode)] = load_run(args["eval"], gt, prefix)
            if group_of(name) == "five":
                os.makedirs(plots, exist_ok=True)
                page_file = "%s-%s.html" % (cond_of(name), mode)
                proc = subprocess.run([args["eval"], "ate", "--gt", gt, "--est", prefix + ".tum", "--align", "sim3",
                                       "--frame-log", prefix + ".csv", "--report", os.path.join(plots, page_file)],
                                      capture_output=True, text=True)
                if proc.returncode != 0:
                    # no pose: the frame log alone
                    proc = subprocess.run([args["eval"], "report", "--frame-log", prefix + ".csv", "--out",
                                           os.path.join(plots, page_file)], capture_output=True, text=True)
                if proc.returncode == 0:
                    runs[(name, mode)]["report"] = os.path.basename(plots) + "/" + page_file
    if missing:
        sys.stderr.write("experiments-eval: no run for %s\n" % ", ".join(missing))
    if not runs:
        sys.stderr.write("experiments-eval: no run to score in %s\n" % out)
        return 1
    extras = {"article_frames": article_frames(args["features"], args["data"]), "missing": missing}
    try:
        with open(os.path.join(out, "determinism.txt")) as f:
            extras["determinism"] = f.read().strip()
    except OSError:
        pass
    page = Page(args["modes"], runs)
    write_page(page, args, extras)
    os.makedirs(os.path.dirname(os.path.abspath(results)), exist_ok=True)
    with open(results, "w") as f:
        f.write("\n".join(page.lines).rstrip() + "\n")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
