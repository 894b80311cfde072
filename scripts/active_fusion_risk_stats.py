#!/usr/bin/env python3
"""Active-fusion risk figures from a run's frames.csv and the sequence's gt_tum.txt:
  corridor: share of frames with gamma_x < 0.2 inside the corridor (GT 10 m < x < L - 10 m) and
            with gamma_x >= 0.2 in the structured parts (within 10 m of the closed start or of the
            facade, |y| < 2 m) and in the open area (x > L + 2 m); L = CORRIDOR_LENGTH (100)
  office:   share of frames with no axis flagged
  multifloor: share of frames flagging z on the stairs (GT |dz/dt| > 0.1 m/s) and elsewhere,
              and by place (shaft, ground-floor and top-floor hallway); with the eigen columns of
              frames.csv, also where the weakest translation direction of sum w n n^T points
              (rotated into the map frame with the row's pose): vertical (|z| > 0.8) or
              horizontal (|z| < 0.3)
  every world: median / p95 ms_risk
Usage: active_fusion_risk_stats.py WORLD FRAMES_CSV GT_TUM [CORRIDOR_LENGTH]"""
import bisect
import csv
import statistics
import sys

world, frames_csv, gt_path = sys.argv[1:4]
length = float(sys.argv[4]) if len(sys.argv) > 4 else 100.0
rows = list(csv.DictReader(open(frames_csv)))
gt = [list(map(float, l.split()[:4])) for l in open(gt_path) if l.strip() and not l.startswith("#")]
gt_t = [g[0] for g in gt]


def gt_at(t):
    i = min(max(bisect.bisect_left(gt_t, t), 1), len(gt) - 1)
    return gt[i] if abs(gt[i][0] - t) < abs(gt[i - 1][0] - t) else gt[i - 1]


def weak_world_z(r):
    """z component (map frame) of the row's weakest translation direction (body axes)."""
    x, y, z, w = (float(r[k]) for k in ("qx", "qy", "qz", "qw"))
    v = [float(r[k]) for k in ("weak_t_x", "weak_t_y", "weak_t_z")]
    # Third row of the rotation matrix of (x, y, z, w) times v.
    return (2 * (x * z - w * y)) * v[0] + (2 * (y * z + w * x)) * v[1] + (1 - 2 * (x * x + y * y)) * v[2]


def share(sel, cond):
    sel = list(sel)
    return f"{sum(1 for r in sel if cond(r))}/{len(sel)} ({100.0 * sum(1 for r in sel if cond(r)) / max(1, len(sel)):.0f} %)"


gx = lambda r: float(r["gamma_x"])
risk_ms = sorted(float(r["ms_risk"]) for r in rows)
print(f"{world}: ms_risk median {statistics.median(risk_ms):.3f}, p95 {risk_ms[int(0.95 * (len(risk_ms) - 1))]:.3f}, max {risk_ms[-1]:.3f}")
if world == "corridor":
    pos = [(r, gt_at(float(r["t"]))) for r in rows]
    inside = [r for r, g in pos if 10 < g[1] < length - 10 and abs(g[2]) < 2]
    ends = [r for r, g in pos if (g[1] < 10 or length - 10 < g[1] < length + 2) and abs(g[2]) < 2]
    open_area = [r for r, g in pos if g[1] > length + 2]
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
    if "weak_t_z" in rows[0]:
        for k, v in [("on the stairs", stairs), ("elsewhere", flat)] + list(place.items()):
            vert = [abs(weak_world_z(r)) for r in v]
            emin = sorted(float(r["trans_eig_1"]) for r in v)
            print(f"  {k}, weakest translation vertical / horizontal: "
                  f"{sum(a > 0.8 for a in vert)} / {sum(a < 0.3 for a in vert)} of {len(v)}, "
                  f"its information share median {statistics.median(emin):.3f}")
else:
    from collections import Counter
    print("  flags:", Counter(r["degenerate"] for r in rows).most_common(5))
