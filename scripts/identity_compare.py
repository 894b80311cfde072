#!/usr/bin/env python3
"""Compares two folders of localizer runs (scripts/identity_runs.sh): per run, frames.csv with its
timing columns (ms_*) left out, trajectory.tum and trajectory_cov.txt, byte for byte.
Exit 0 when every run is identical, 1 otherwise.
    scripts/identity_compare.py OUT_BEFORE OUT_AFTER
"""
import csv
import os
import sys


def read(path):
    return open(path).read() if os.path.exists(path) else None


def main(a, b):
    runs = sorted(n for n in os.listdir(a) if os.path.isdir(os.path.join(a, n)))
    if not runs:
        print(f"{a}: no runs")
        return 1
    bad = 0
    for n in runs:
        fa, fb = os.path.join(a, n, "frames.csv"), os.path.join(b, n, "frames.csv")
        if not (os.path.exists(fa) and os.path.exists(fb)):
            print(f"{n}: frames.csv missing in {a if not os.path.exists(fa) else b}")
            bad += 1
            continue
        ra, rb = list(csv.reader(open(fa))), list(csv.reader(open(fb)))
        if ra[0] != rb[0]:
            print(f"{n}: the columns differ")
            bad += 1
            continue
        keep = [i for i, h in enumerate(ra[0]) if not h.startswith("ms_") and not h.endswith("_ms")]
        rows = [k for k in range(1, min(len(ra), len(rb))) if any(ra[k][i] != rb[k][i] for i in keep)]
        same_traj = read(os.path.join(a, n, "trajectory.tum")) == read(os.path.join(b, n, "trajectory.tum"))
        same_cov = read(os.path.join(a, n, "trajectory_cov.txt")) == read(os.path.join(b, n, "trajectory_cov.txt"))
        ok = len(ra) == len(rb) and not rows and same_traj and same_cov
        bad += not ok
        what = "identical" if ok else "DIFFERENT"
        detail = ""
        if rows:
            k = rows[0]
            cols = [ra[0][i] for i in keep if ra[k][i] != rb[k][i]]
            detail = f" (first at frame row {k}: {', '.join(cols[:6])})"
        print(f"{n}: {len(ra) - 1} / {len(rb) - 1} frames, {what}{detail}"
              f"{'' if same_traj else ', trajectory differs'}{'' if same_cov else ', covariance differs'}")
    print("all identical (but the times)" if not bad else f"{bad} of {len(runs)} runs differ")
    return 1 if bad else 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
