#!/usr/bin/env python3
"""Seed corpora for the libFuzzer targets (scripts/fuzz.sh), cut from the real files in the
shared data folder: small enough (tens of points) for fast executions, real in every byte.

    fuzz_seeds.py DATA_DIR REPO_DIR OUT_DIR   ->  OUT_DIR/{pcd,ply,kitti_bin,tum,ini,map_tiles}/seed-*
"""
import glob
import os
import struct
import sys

N = 40  # points per cut-down cloud


def write(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def pcd_seeds(pcd_path, out, tag):
    """Real PCD header with N points (binary, as recorded) and the same points in ASCII."""
    raw = open(pcd_path, "rb").read()
    header, fields, sizes, types, counts, i = [], [], [], [], [], 0
    while True:
        j = raw.index(b"\n", i)
        line = raw[i:j].decode()
        i = j + 1
        header.append(line)
        key, _, val = line.partition(" ")
        if key == "FIELDS":
            fields = val.split()
        elif key == "SIZE":
            sizes = [int(v) for v in val.split()]
        elif key == "TYPE":
            types = val.split()
        elif key == "COUNT":
            counts = [int(v) for v in val.split()]
        elif key == "DATA":
            break
    if not header[-1].endswith("binary") or set(types) != {"F"} or set(sizes) != {4}:
        return
    stride = sum(s * c for s, c in zip(sizes, counts))
    body = raw[i:i + N * stride]

    def hdr(data):
        h = []
        for line in header:
            key = line.split(" ")[0]
            if key in ("WIDTH", "POINTS"):
                line = f"{key} {N}"
            elif key == "DATA":
                line = f"DATA {data}"
            h.append(line)
        return "\n".join(h) + "\n"

    write(f"{out}/pcd/seed-{tag}-binary.pcd", hdr("binary").encode() + body)
    nf = stride // 4
    rows = [struct.unpack_from(f"<{nf}f", body, k * stride) for k in range(N)]
    ascii_body = "".join(" ".join(f"{v:.6g}" for v in r) + "\n" for r in rows)
    write(f"{out}/pcd/seed-{tag}-ascii.pcd", hdr("ascii") + ascii_body)


def kitti_points(bin_path):
    raw = open(bin_path, "rb").read(N * 16)
    return raw, [struct.unpack_from("<4f", raw, 16 * k) for k in range(len(raw) // 16)]


def ply_seeds(points, out, tag):
    """The KITTI points as PLY: ASCII, binary little- and big-endian (x y z intensity)."""
    def header(fmt):
        return (f"ply\nformat {fmt} 1.0\ncomment cut from KITTI 00 ({tag})\n"
                f"element vertex {len(points)}\nproperty float x\nproperty float y\n"
                "property float z\nproperty float intensity\nend_header\n")
    write(f"{out}/ply/seed-{tag}-ascii.ply",
          header("ascii") + "".join(" ".join(f"{v:.6g}" for v in p) + "\n" for p in points))
    write(f"{out}/ply/seed-{tag}-le.ply",
          header("binary_little_endian").encode() + b"".join(struct.pack("<4f", *p) for p in points))
    write(f"{out}/ply/seed-{tag}-be.ply",
          header("binary_big_endian").encode() + b"".join(struct.pack(">4f", *p) for p in points))


def main():
    data, repo, out = sys.argv[1:4]
    for p in sorted(glob.glob(f"{data}/campus-ouster/scans/*.pcd"))[:2]:
        pcd_seeds(p, out, "campus-" + os.path.basename(p)[:-4])
    for p in sorted(glob.glob(f"{data}/scan-pair-outdoor/*.pcd"))[:1]:
        pcd_seeds(p, out, "pair-" + os.path.basename(p)[:-4])
    for p in sorted(glob.glob(f"{data}/kitti00-mini/velodyne/*.bin"))[:2]:
        tag = "kitti-" + os.path.basename(p)[:-4]
        raw, pts = kitti_points(p)
        write(f"{out}/kitti_bin/seed-{tag}.bin", raw)
        ply_seeds(pts, out, tag)
    for name, p in (("kitti", f"{data}/kitti00-mini/gt_velodyne_tum.txt"),
                    ("campus", f"{data}/campus-ouster/gt_tum.txt")):
        if os.path.exists(p):
            lines = open(p).read().splitlines(True)
            write(f"{out}/tum/seed-{name}.tum", "".join(lines[:12]))
    for p in sorted(glob.glob(f"{repo}/ini/*.ini")) + sorted(glob.glob(f"{repo}/ini/sensors/*.ini")):
        write(f"{out}/ini/seed-{os.path.basename(p)}", open(p).read())
    write(f"{out}/ini/seed-set.ini",
          "[localization]\nmethod=icp\n--set localization.max_corr_dist=0.7\n"
          "--set features.voxel_size=0.4\n--set risk.degenerate_threshold=0.2\n")
    write(f"{out}/map_tiles/seed-index.csv",
          "# superloc map tiles: tile (ix, iy) holds the points with floor(x/s) = ix, floor(y/s) = iy\n"
          "tile_size,50\nix,iy,points,file\n0,0,2,t.pcd\n-1,3,2,t.pcd\n")
    for sub in ("pcd", "ply", "kitti_bin", "tum", "ini", "map_tiles"):
        n = len(os.listdir(f"{out}/{sub}")) if os.path.isdir(f"{out}/{sub}") else 0
        print(f"seeds {sub}: {n}")


if __name__ == "__main__":
    main()
