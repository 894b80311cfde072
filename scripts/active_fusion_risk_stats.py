#!/usr/bin/env python3
"""Risk figures of issue 5 from a run's frames.csv and the sequence's gt_tum.txt:
  corridor: share of frames with gamma_x < 0.2 inside the corridor (GT 10 m < x < 90 m) and with
            gamma_x >= 0.2 in the structured parts (within 10 m of the closed start or of the
            facade, |y| < 2 m) and in the open area (x > 102 m)
  office:   share of frames with no axis flagged
  multifloor: share of frames flagging z on the stairs (GT |dz/dt| > 0.1 m/s) and elsewhere,
              and by place (shaft, ground-floor and top-floor hallway)
  every world: median / p95 ms_risk
Usage: active_fusion_risk_stats.py WORLD FRAMES_CSV GT_TUM"""
import bisect
import csv
import statistics
import sys

world, frames_csv, gt_path = sys.argv[1:4]
rows = list(csv.DictReader(open(frames_csv)))
gt = [list(map(float, l.split()[:4])) for l in open(gt_path) if l.strip() and not l.startswith("#")]
gt_t = [g[0] for g in gt]


def gt_at(t):
    i = min(max(bisect.bisect_left(gt_t, t), 1), len(gt) - 1)
    return gt[i] if abs(gt[i][0] - t) < abs(gt[i - 1][0] - t) else gt[i - 1]


def share(sel, cond):
    sel = list(sel)
    return f"{sum(1 for r in sel if cond(r))}/{len(sel)} ({100.0 * sum(1 for r in sel if cond(r)) / max(1, len(sel)):.0f} %)"


gx = lambda r: float(r["gamma_x"])
risk_ms = sorted(float(r["ms_risk"]) for r in rows)
print(f"{world}: ms_risk median {statistics.median(risk_ms):.3f}, p95 {risk_ms[int(0.95 * (len(risk_ms) - 1))]:.3f}, max {risk_ms[-1]:.3f}")
if world == "corridor":
    pos = [(r, gt_at(float(r["t"]))) for r in rows]
    inside = [r for r, g in pos if 10 < g[1] < 90 and abs(g[2]) < 2]
    ends = [r for r, g in pos if (g[1] < 10 or 90 < g[1] < 102) and abs(g[2]) < 2]
    open_area = [r for r, g in pos if g[1] > 102]
    print("  inside the corridor, gamma_x < 0.2:", share(inside, lambda r: gx(r) < 0.2))
    print("  corridor ends (closed start, facade), gamma_x >= 0.2:", share(ends, lambda r: gx(r) >= 0.2))
    print("  open area, gamma_x >= 0.2:", share(open_area, lambda r: gx(r) >= 0.2))
elif world == "office":
    print("  no axis flagged:", share(rows, lambda r: r["degenerate"] == ""))
elif world == "multifloor":
    stairs, flat = [], []
    for r in rows:
        t = float(r["t"])
        a, b = gt_at(t - 0.25), gt_at(t + 0.25)
        vz = (b[3] - a[3]) / max(1e-6, b[0] - a[0])
        (stairs if abs(vz) > 0.1 else flat).append(r)
    print("  on the stairs, z flagged:", share(stairs, lambda r: "z" in r["degenerate"]))
    print("  elsewhere, z flagged:", share(flat, lambda r: "z" in r["degenerate"]))
    # By place: the stairwell shaft (GT x > 0.2 m: flights and landings) and the two hallways.
    place = {"shaft": [], "ground-floor hallway": [], "top-floor hallway": []}
    for r in rows:
        g = gt_at(float(r["t"]))
        place["shaft" if g[1] > 0.2 else ("top-floor hallway" if g[3] > 6 else "ground-floor hallway")].append(r)
    for k, v in place.items():
        print(f"  {k}, z flagged:", share(v, lambda r: "z" in r["degenerate"]))
else:
    from collections import Counter
    print("  flags:", Counter(r["degenerate"] for r in rows).most_common(5))
