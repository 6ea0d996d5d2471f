#!/usr/bin/env python3
"""The table of scripts/lane-bench.sh: one row per replayed route, then the mean and median ATE
over the routes, and with --baseline each route against an earlier run of the same renders.

usage: lane-bench-eval.py --eval ALE_EVAL --renders DIR --runs DIR [--baseline RUNS] NAME|EVENT ...

Rows as scripts/loop-bench-eval.py's (path m, frames, posed %, resets, maps, reloc, loops,
refused, merges, ATE cm and %: ale-eval ate --align sim3's ate_rmse over all poses as one map, in
cm and in % of the ground-truth path of the posed frames).
With --baseline RUNS (the runs folder of an earlier bench over the same renders): `base %`, that
run's ATE %, and `ratio`, this run's over it. The summary: over the routes with an ATE, its mean,
median and worst; the routes with a reset and the lowest posed share; with a baseline, over the
routes both runs scored, the routes this run is better and worse on (a route within 1 % of the
baseline's figure is even) and the two-sided exact sign test of that split (ties left out), and
both means and medians. Exit status 1 when a route has no ATE.
"""
import importlib.util
import os
import statistics
import sys


def _load(module, file):
    spec = importlib.util.spec_from_file_location(module, os.path.join(os.path.dirname(os.path.abspath(__file__)), file))
    m = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(m)
    return m


lbe = _load("loop_bench_eval", "loop-bench-eval.py")
xpe = _load("experiments_eval", "experiments-eval.py")
pbe = lbe.pbe

EVEN = 0.01  # relative difference within which a route counts as even against the baseline

COLUMNS = [("route", "name", None), ("path m", "path_m", ".1f"), ("frames", "frames", None),
           ("posed %", "posed", ".1f"), ("resets", "resets", None), ("maps", "maps", None), ("reloc", "reloc", None),
           ("loops", "loops", None), ("refused", "refused", None), ("merges", "merges", None),
           ("ATE cm", "ate_cm", ".2f"), ("ATE %", "ate_pct", ".3f")]
BASE_COLUMNS = [("base %", "base_pct", ".3f"), ("ratio", "ratio", ".2f")]


def compare(pairs):
    """(better, worse, even) over (this, baseline) figures, lower being better."""
    better = sum(1 for a, b in pairs if a < b * (1.0 - EVEN))
    worse = sum(1 for a, b in pairs if a > b * (1.0 + EVEN))
    return better, worse, len(pairs) - better - worse


def main(argv):
    baseline = None
    if "--baseline" in argv:
        i = argv.index("--baseline")
        if i + 1 >= len(argv):
            sys.stderr.write(__doc__)
            return 2
        baseline = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    cli = pbe.parse_cli(argv, __doc__)
    if cli is None:
        return 2
    args, items = cli
    columns = COLUMNS + (BASE_COLUMNS if baseline else []) + [("note", "note", None)]
    print("| " + " | ".join(c[0] for c in columns) + " |")
    print("|" + "---|" * len(columns))
    rows = []
    for item in items:
        name, _, event = item.partition("|")
        if os.path.exists(os.path.join(args["--runs"], name + ".tum")):
            r = lbe.row(args["--eval"], args["--renders"], args["--runs"], name, event or "-")
        else:
            r = {"note": "no trajectory file"}
        r["name"] = name
        if baseline:
            b = {}
            lbe.precise_ate(args["--eval"], args["--renders"], baseline, name, b)
            r["base_pct"] = b.get("ate_pct")
            if r.get("ate_pct") is not None and b.get("ate_pct"):
                r["ratio"] = r["ate_pct"] / b["ate_pct"]
        rows.append(r)
        print("| " + " | ".join(lbe.cell(r, key, spec) for _, key, spec in columns) + " |")
    scored = [r for r in rows if r.get("ate_pct") is not None]
    print()
    if scored:
        worst = max(scored, key=lambda r: r["ate_pct"])
        print("ATE %% over %d routes: mean %.3f, median %.3f, worst %.3f (%s)" % (
            len(scored), statistics.mean(r["ate_pct"] for r in scored), statistics.median(r["ate_pct"] for r in scored),
            worst["ate_pct"], worst["name"]))
    reset = [r["name"] for r in rows if r.get("resets")]
    posed = [r["posed"] for r in rows if r.get("posed") is not None]
    print("routes with a reset: %d%s; posed %% at least %s" % (
        len(reset), " (" + ", ".join(reset) + ")" if reset else "", pbe.fmt(min(posed) if posed else None, ".1f")))
    if baseline:
        pairs = [(r["ate_pct"], r["base_pct"]) for r in scored if r.get("base_pct") is not None]
        better, worse, even = compare(pairs)
        if pairs:
            print("against %s over %d routes: better %d, worse %d, even %d (sign test p = %.3f); mean %.3f against "
                  "%.3f, median %.3f against %.3f" % (
                      baseline, len(pairs), better, worse, even, xpe.sign_test(better, worse),
                      statistics.mean(a for a, _ in pairs), statistics.mean(b for _, b in pairs),
                      statistics.median(a for a, _ in pairs), statistics.median(b for _, b in pairs)))
        else:
            print("against %s: no route scored by both" % baseline)
    missing = [r["name"] for r in rows if r.get("ate_pct") is None]
    if missing:
        print("no ATE for: " + ", ".join(missing))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
