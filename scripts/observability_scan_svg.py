#!/usr/bin/env python3
"""Top view of an observability_scan.ply (binary PLY x y z float, red green blue uchar, as
superloc-localize writes it): xy cells coloured by their majority translation label (x red,
y green, z blue, none grey), like the paper's Fig. 4.
Usage: observability_scan_svg.py SCAN.ply OUT.svg [cell_m] [xmin xmax ymin ymax]"""
import collections
import struct
import sys

src, out = sys.argv[1], sys.argv[2]
cell = float(sys.argv[3]) if len(sys.argv) > 3 else 0.5
box = list(map(float, sys.argv[4:8])) if len(sys.argv) > 7 else None
with open(src, "rb") as f:
    n = 0
    while True:
        line = f.readline()
        if line.startswith(b"element vertex"):
            n = int(line.split()[2])
        if line.startswith(b"end_header"):
            break
    data = f.read()
votes = collections.defaultdict(collections.Counter)
for i in range(n):
    x, y, z, r, g, b = struct.unpack_from("<fffBBB", data, 15 * i)
    if box and not (box[0] <= x <= box[1] and box[2] <= y <= box[3]):
        continue
    votes[(int(x // cell), int(y // cell))][(r, g, b)] += 1
if not votes:
    sys.exit("no points in the box")
xs = [k[0] for k in votes]
ys = [k[1] for k in votes]
x0, x1, y0, y1 = min(xs), max(xs) + 1, min(ys), max(ys) + 1
scale = max(1, int(1200 / (x1 - x0)))
W, H = (x1 - x0) * scale, (y1 - y0) * scale
with open(out, "w") as f:
    f.write(f'<svg xmlns="http://www.w3.org/2000/svg" width="{W:.0f}" height="{H + 20:.0f}">\n')
    f.write(f'<rect width="100%" height="100%" fill="white"/>\n')
    for (cx, cy), c in votes.items():
        (r, g, b), _ = c.most_common(1)[0]
        f.write(f'<rect x="{(cx - x0) * scale:.0f}" y="{(y1 - 1 - cy) * scale:.0f}" '
                f'width="{scale}" height="{scale}" fill="#{r:02x}{g:02x}{b:02x}"/>\n')
    f.write(f'<text x="4" y="{H + 15:.0f}" font-size="12">{src.split("/")[-3] if src.count("/") > 2 else src}: '
            f'{cell} m cells, majority translation label (x red, y green, z blue)</text>\n</svg>\n')
