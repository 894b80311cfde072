#!/usr/bin/env python3
"""A stress study's plot: one metric of superloc-bench's results.json against the swept variable,
one line per method, as an SVG (log-scale y), plus the same numbers as a Markdown table on stdout.
  sweep_plot.py RESULTS_JSON METRIC XLABEL OUT_SVG SEQ=X [SEQ=X ...]
METRIC: ate (ATE RMSE [m]) or outliers (map outliers [%]). SEQ=X maps a sequence of the suite to
its value of the swept variable, e.g. len50=50 len100=100. A sequence run over several seeds
(`seeds = 1 2 3`: sequences NAME_s1, NAME_s2, ...) is one point: the mean over its seeds, with
the seeds' min-max in the table.
A run that failed or has no value is left out of its line (and shown as "–" in the table; a
seed mean over fewer seeds than the others says how many, e.g. "n=2")."""
import json
import math
import re
import sys

results, metric, xlabel, out_svg = sys.argv[1:5]
xs = {}
for arg in sys.argv[5:]:
    seq, x = arg.split("=")
    xs[seq] = float(x)
runs = json.load(open(results))["runs"]


def value(run):
    m = run.get("metrics") or {}
    if metric == "ate":
        v = ((m.get("ate") or {}).get("trans_m") or {}).get("rmse")
    elif metric == "outliers":
        v = (m.get("map") or {}).get("outlier_percent")
    else:
        sys.exit("metric must be ate or outliers")
    return v if isinstance(v, (int, float)) and math.isfinite(v) else None


methods, per_seed = [], {}
for r in runs:
    seq = r["sequence"]
    if seq not in xs:
        seq = re.sub(r"_s[0-9]+$", "", seq)
    if seq not in xs:
        continue
    if r["method"] not in per_seed:
        methods.append(r["method"])
        per_seed[r["method"]] = {}
    per_seed[r["method"]].setdefault(xs[seq], []).append(value(r))
# One point per sequence: the mean over its seeds (None when no seed has a value).
series = {m: {x: (sum(v for v in vs if v is not None) / len([v for v in vs if v is not None])
                  if any(v is not None for v in vs) else None)
              for x, vs in per_x.items()} for m, per_x in per_seed.items()}
xvals = sorted(set(xs.values()))
label = "ATE RMSE [m]" if metric == "ate" else "map outliers [%]"

print("| Method | " + " | ".join("%g" % x for x in xvals) + " |")
print("|---|" + "---:|" * len(xvals))
for m in methods:
    cells = []
    for x in xvals:
        v = series[m].get(x)
        fmt = "%.3f" if metric == "ate" else "%.2f"
        vs = [u for u in per_seed[m].get(x, []) if u is not None]
        cell = "–" if v is None else fmt % v
        if len(vs) > 1:
            cell += " (" + fmt % min(vs) + "–" + fmt % max(vs) + ")"
        if v is not None and len(vs) < len(per_seed[m].get(x, [])):
            cell += " n=%d" % len(vs)
        cells.append(cell)
    print("| " + m + " | " + " | ".join(cells) + " |")

W, H, L, R, T, B = 640, 400, 70, 150, 30, 50
vals = [v for m in methods for v in series[m].values() if v is not None and v > 0]
lo = 10 ** math.floor(math.log10(min(vals))) if vals else 0.01
hi = 10 ** math.ceil(math.log10(max(vals))) if vals else 1.0
if hi <= lo:
    hi = lo * 10


def px(x):
    return L + (W - L - R) * (x - xvals[0]) / max(1e-9, xvals[-1] - xvals[0])


def py(v):
    return T + (H - T - B) * (1 - (math.log10(max(v, lo)) - math.log10(lo)) / (math.log10(hi) - math.log10(lo)))


colors = ["#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"]
svg = ['<?xml version="1.0" encoding="UTF-8"?>',
       '<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">' % (W, H),
       '<rect width="100%" height="100%" fill="white"/>']
d = 0
while lo * 10 ** d <= hi * 1.0001:
    v = lo * 10 ** d
    svg.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (L, py(v), W - R, py(v)))
    svg.append('<text x="%d" y="%.1f" text-anchor="end">%g</text>' % (L - 5, py(v) + 4, v))
    d += 1
for x in xvals:
    svg.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#eee"/>' % (px(x), T, px(x), H - B))
    svg.append('<text x="%.1f" y="%d" text-anchor="middle">%g</text>' % (px(x), H - B + 16, x))
svg.append('<text x="%d" y="%d" text-anchor="middle">%s</text>' % ((L + W - R) // 2, H - 10, xlabel))
svg.append('<text x="15" y="%d" transform="rotate(-90 15 %d)" text-anchor="middle">%s</text>' % (H // 2, H // 2, label))
for i, m in enumerate(methods):
    c = colors[i % len(colors)]
    pts = [(px(x), py(series[m][x])) for x in xvals if series[m].get(x) is not None]
    if pts:
        svg.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>' %
                   (c, " ".join("%.1f,%.1f" % p for p in pts)))
        for p in pts:
            svg.append('<circle cx="%.1f" cy="%.1f" r="3" fill="%s"/>' % (p[0], p[1], c))
    svg.append('<text x="%d" y="%d" fill="%s">%s</text>' % (W - R + 10, T + 16 * (i + 1), c, m))
svg.append("</svg>")
open(out_svg, "w").write("\n".join(svg) + "\n")
