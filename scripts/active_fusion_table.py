#!/usr/bin/env python3
"""Markdown table of an active_fusion_experiments.sh output folder: OUT/<world>/<method>/
{eval.json, frames.csv}. Usage: active_fusion_table.py OUT"""
import csv
import json
import os
import statistics
import sys

out = sys.argv[1]
print("| world | method | ATE RMSE [m] | ATE max [m] | map outliers [%] | frames with prior | "
      "frames flagged | median ms/frame | median ms risk |")
print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
for w in sorted(os.listdir(out)):
    wdir = os.path.join(out, w)
    if not os.path.isdir(wdir):
        continue
    for m in ["icp", "ndt", "superloc", "superloc_nocap", "passive", "eigen_remap", "eigen_remap_t0.01"]:
        d = os.path.join(wdir, m)
        if not os.path.exists(os.path.join(d, "eval.json")):
            continue
        e = json.load(open(os.path.join(d, "eval.json")))
        rows = list(csv.DictReader(open(os.path.join(d, "frames.csv"))))
        n = len(rows)
        prior = sum(int(r["prior_used"]) for r in rows)
        flagged = sum(1 for r in rows if r["degenerate"])
        risk = statistics.median(float(r["ms_risk"]) for r in rows)
        mp = e.get("map", {}) or {}
        outl = mp.get("outlier_percent", float("nan"))
        print(f"| {w} | {m} | {e['ate']['trans_m']['rmse']:.3f} | {e['ate']['trans_m']['max']:.3f} | "
              f"{outl:.2f} | {prior}/{n} | {flagged}/{n} | {e['timing']['median_ms']:.1f} | {risk:.3f} |")
