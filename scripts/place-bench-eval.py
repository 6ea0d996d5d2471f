#!/usr/bin/env python3
"""The table of scripts/place-bench.sh: one row per replayed sequence.

usage: place-bench-eval.py --eval ALE_EVAL --renders DIR --runs DIR NAME|EVENT ...

For each NAME: DIR/renders/NAME (groundtruth.txt, mav0/cam0/data.csv) and DIR/runs/NAME.tum,
NAME.frames.csv, NAME.log (ale-slamd's). EVENT is -, blackout:START,DURATION or kidnap:AT,TO,GAP
(the ale-render options). Columns:
  frames     frames replayed
  posed %    poses written / frames from the first pose on (after initialisation)
  resets     map_id changes in the frame log
  maps       map segments of the trajectory file with at least one pose ("# map N" lines)
  reloc      frames whose frame-log state is `relocalized`
  ATE        ale-eval ate --align sim3 over all poses as if they were one map: cm and % of the
             ground-truth path (ale-eval's summary); with several maps this mixes frames
  ATE/map    each map aligned on its own (Sim(3), maps of 3 poses or more), RMS over their poses:
             cm and % of the same path; poses of smaller maps are left out (counted in `left`)
  back s     blackout: seconds from the light coming back to the first pose after it; kidnap:
             seconds from the first frame after the jump to the first pose from there
  err cm     that pose's position error in the frame of the map the run was in before the event
             (that map aligned on its own, Sim(3), all of its poses): a pose in a new map is in
             another frame and its error says so
  same map   whether that pose is in the map the run was in before the event
  render s   ale-render's time for the sequence (scene build + frames, from its render.log)
"""
import math
import os
import re
import subprocess
import sys


def read_tum_segments(path):
    """Segments of a TUM file split at '# map N' lines: list of (map, [(t, x, y, z)])."""
    segs = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line:
                continue
            m = re.match(r"#\s*map\s+(\S+)", line)
            if m:
                segs.append((m.group(1), []))
                continue
            if line.startswith("#"):
                continue
            v = line.split()
            if not segs:
                segs.append(("?", []))
            segs[-1][1].append((float(v[0]), float(v[1]), float(v[2]), float(v[3])))
    return [s for s in segs if s[1]]


def read_gt(path):
    out = {}
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = line.split()
            out[round(float(v[0]) * 1e6)] = (float(v[1]), float(v[2]), float(v[3]))
    return out


def read_frame_log(path):
    rows = []
    with open(path) as f:
        header = f.readline().lstrip("#").strip().split(",")
        for line in f:
            v = line.strip().split(",")
            if len(v) == len(header):
                rows.append(dict(zip(header, v)))
    return rows


def sym_eig_max(n4):
    """Eigenvector of the largest eigenvalue of a symmetric 4x4 matrix (Jacobi rotations)."""
    a = [row[:] for row in n4]
    v = [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]
    for _ in range(100):
        off = sum(a[i][j] ** 2 for i in range(4) for j in range(4) if i != j)
        if off < 1e-30:
            break
        for p in range(3):
            for q in range(p + 1, 4):
                if abs(a[p][q]) < 1e-300:
                    continue
                theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q])
                t = math.copysign(1.0, theta) / (abs(theta) + math.sqrt(theta * theta + 1.0))
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                for k in range(4):
                    akp, akq = a[k][p], a[k][q]
                    a[k][p], a[k][q] = c * akp - s * akq, s * akp + c * akq
                for k in range(4):
                    apk, aqk = a[p][k], a[q][k]
                    a[p][k], a[q][k] = c * apk - s * aqk, s * apk + c * aqk
                for k in range(4):
                    vkp, vkq = v[k][p], v[k][q]
                    v[k][p], v[k][q] = c * vkp - s * vkq, s * vkp + c * vkq
    best = max(range(4), key=lambda i: a[i][i])
    return [v[k][best] for k in range(4)]


def sim3_align(est, gt):
    """Scale s, rotation R (3x3 lists) and translation t minimising |s R est + t - gt|^2 (Horn's
    quaternion method; the scale as Umeyama's)."""
    n = len(est)
    me = [sum(p[i] for p in est) / n for i in range(3)]
    mg = [sum(p[i] for p in gt) / n for i in range(3)]
    e = [[p[i] - me[i] for i in range(3)] for p in est]
    g = [[p[i] - mg[i] for i in range(3)] for p in gt]
    s_ = [[sum(e[k][i] * g[k][j] for k in range(n)) for j in range(3)] for i in range(3)]
    (sxx, sxy, sxz), (syx, syy, syz), (szx, szy, szz) = s_
    n4 = [[sxx + syy + szz, syz - szy, szx - sxz, sxy - syx],
          [syz - szy, sxx - syy - szz, sxy + syx, szx + sxz],
          [szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy],
          [sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz]]
    w, x, y, z = sym_eig_max(n4)
    r = [[w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
         [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
         [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z]]
    var_e = sum(c * c for p in e for c in p)
    num = sum(g[k][i] * sum(r[i][j] * e[k][j] for j in range(3)) for k in range(n) for i in range(3))
    s = num / var_e if var_e > 0 else 1.0
    t = [mg[i] - s * sum(r[i][j] * me[j] for j in range(3)) for i in range(3)]
    return s, r, t


def apply(sim, p):
    s, r, t = sim
    return [s * sum(r[i][j] * p[j] for j in range(3)) + t[i] for i in range(3)]


def dist(a, b):
    return math.sqrt(sum((a[i] - b[i]) ** 2 for i in range(3)))


def pairs_of(poses, gt):
    """(est xyz, gt xyz, t) for the poses with ground truth at the same time (1 ms)."""
    out = []
    for t, x, y, z in poses:
        key = round(t * 1e6)
        g = None
        for k in (key, key - 1, key + 1):
            if k in gt:
                g = gt[k]
                break
        if g is None:
            # Nearest within 1 ms (rendered frames share their timestamps with the ground truth).
            for dk in range(2, 1001):
                if key + dk in gt or key - dk in gt:
                    g = gt.get(key + dk, gt.get(key - dk))
                    break
        if g is not None:
            out.append(((x, y, z), g, t))
    return out


def ale_eval_summary(ale_eval, gt_path, est_path):
    """(ATE cm, % of path, path m) from ale-eval's summary line, or None with its complaint."""
    proc = subprocess.run([ale_eval, "ate", "--gt", gt_path, "--est", est_path, "--align", "sim3", "--print",
                           "summary"], capture_output=True, text=True)
    m = re.search(r"ATE ([0-9.]+) cm .*?, ([0-9.]+) % of the ([0-9.]+) m path", proc.stdout)
    if not m:
        return None, (proc.stdout + proc.stderr).strip().splitlines()[:1]
    return (float(m.group(1)), float(m.group(2)), float(m.group(3))), None


def fmt(v, spec):
    return "-" if v is None else format(v, spec)


def row(ale_eval, renders, runs, name, event):
    run = os.path.join(runs, name)
    gt_path = os.path.join(renders, name, "groundtruth.txt")
    out = {"name": name}
    try:
        with open(os.path.join(renders, name, "render.log")) as f:
            m = re.search(r"^ale-render: (\d+) frames.*?^time: scene ([0-9.]+) s, ([0-9.]+) ms per frame", f.read(),
                          re.S | re.M)
        if m:
            out["render_s"] = float(m.group(2)) + int(m.group(1)) * float(m.group(3)) / 1000.0
    except OSError:
        pass
    if not os.path.exists(run + ".frames.csv"):
        out["note"] = "no replay"
        return out
    frames = read_frame_log(run + ".frames.csv")
    gt = read_gt(gt_path)
    segs = read_tum_segments(run + ".tum")
    poses = [p for _, s in segs for p in s]
    out["frames"] = len(frames)
    # Posed share from the first pose on.
    stamps = [int(f["timestamp_ns"]) for f in frames]
    if poses:
        first = min(i for i, ts in enumerate(stamps) if ts >= round(poses[0][0] * 1e9) - 500000)
        out["posed"] = 100.0 * len(poses) / max(1, len(frames) - first)
    ids = [f.get("map_id", "") for f in frames]
    out["resets"] = sum(1 for a, b in zip(ids, ids[1:]) if a != b)
    out["maps"] = len(segs)
    out["reloc"] = sum(1 for f in frames if f.get("state") == "relocalized")
    if not poses:
        out["note"] = "no pose"
        return out
    summary, err = ale_eval_summary(ale_eval, gt_path, run + ".tum")
    if summary:
        out["ate_cm"], out["ate_pct"], path_m = summary
    else:
        out["note"] = "ale-eval: " + " ".join(err)
        path_m = None
    # Each map on its own: write its poses as a TUM file for ale-eval, pool the squared errors.
    sse, n_used, left = 0.0, 0, 0
    sims = []
    for i, (_, seg) in enumerate(segs):
        pr = pairs_of(seg, gt)
        if len(pr) < 3:
            left += len(seg)
            sims.append(None)
            continue
        sim = sim3_align([p[0] for p in pr], [p[1] for p in pr])
        sims.append(sim)
        sse += sum(dist(apply(sim, e), g) ** 2 for e, g, _ in pr)
        n_used += len(pr)
    if n_used:
        out["ate_map_cm"] = 100.0 * math.sqrt(sse / n_used)
        if path_m:
            out["ate_map_pct"] = out["ate_map_cm"] / path_m
    out["left"] = left
    # Cross-check: one map's own alignment must reproduce ale-eval's figure.
    if len(segs) == 1 and summary and "ate_map_cm" in out and abs(out["ate_map_cm"] - out["ate_cm"]) > 0.05 * out["ate_cm"] + 0.1:
        out["note"] = "alignment differs from ale-eval's (%.1f vs %.1f cm)" % (out["ate_map_cm"], out["ate_cm"])
    # The event: when the view came back, the first pose after it.
    t0 = int(open(os.path.join(renders, name, "mav0", "cam0", "data.csv")).readlines()[1].split(",")[0]) * 1e-9
    back = None
    if event.startswith("blackout:"):
        start, dur = (float(v) for v in event.split(":", 1)[1].split(","))
        back = t0 + start + dur
    elif event.startswith("kidnap:"):
        at, _to, gap = (float(v) for v in event.split(":", 1)[1].split(","))
        back = t0 + at + gap  # trajectory starts at 0 (no --start in the suite): drive time = at
    if back is not None:
        before = [(i, p) for i, (_, s) in enumerate(segs) for p in s if p[0] < back - 1e-6]
        after = [(i, p) for i, (_, s) in enumerate(segs) for p in s if p[0] >= back - 1e-6]
        if after:
            i, p = after[0]
            out["back_s"] = p[0] - back
            pr = pairs_of([p], gt)
            frame = before[-1][0] if before else i
            if sims[frame] is not None and pr:
                out["err_cm"] = 100.0 * dist(apply(sims[frame], pr[0][0]), pr[0][1])
            out["same"] = "yes" if before and before[-1][0] == i else "no"
        else:
            out["same"] = "never"
    return out


def parse_cli(argv, doc):
    """--eval, --renders, --runs and the NAME|EVENT items; None (the usage written) when wrong."""
    args = {}
    rest = []
    i = 1
    while i < len(argv):
        if argv[i] in ("--eval", "--renders", "--runs") and i + 1 < len(argv):
            args[argv[i]] = argv[i + 1]
            i += 2
        else:
            rest.append(argv[i])
            i += 1
    if set(args) != {"--eval", "--renders", "--runs"} or not rest:
        sys.stderr.write(doc)
        return None
    return args, rest


def main(argv):
    cli = parse_cli(argv, __doc__)
    if cli is None:
        return 2
    args, rest = cli
    print("| sequence | frames | posed % | resets | maps | reloc | ATE cm | ATE % | ATE/map cm | ATE/map % | "
          "back s | err cm | same map | render s | note |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for item in rest:
        name, _, event = item.partition("|")
        r = row(args["--eval"], args["--renders"], args["--runs"], name, event or "-")
        note = r.get("note", "")
        if r.get("left"):
            note = (note + "; " if note else "") + "%d poses in maps of < 3" % r["left"]
        print("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            name, r.get("frames", "-"), fmt(r.get("posed"), ".1f"), r.get("resets", "-"), r.get("maps", "-"),
            r.get("reloc", "-"), fmt(r.get("ate_cm"), ".1f"), fmt(r.get("ate_pct"), ".2f"),
            fmt(r.get("ate_map_cm"), ".1f"), fmt(r.get("ate_map_pct"), ".2f"), fmt(r.get("back_s"), ".2f"),
            fmt(r.get("err_cm"), ".1f"), r.get("same", "-" if event in ("", "-") else "?"), fmt(r.get("render_s"), ".0f"),
            note))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
