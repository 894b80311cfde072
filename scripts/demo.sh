#!/usr/bin/env bash
# Installs the dependencies, builds, and runs the main job on a bundled demo:
# KITTI 00 (first 16 scans, ../shared/data/kitti00-mini) -> rawlog -> prior map from its own
# scans -> localize every scan from a start perturbed by (0.5 m, 0.5 m, 0.2 m, 5 deg yaw) ->
# evaluate against ground truth. Outputs in ./out/demo.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
BIN=build/bin
DATA=${SUPERLOC_SHARED_DATA:-../shared/data}/kitti00-mini
OUT=out/demo
if [ ! -d "$DATA" ]; then
  echo "demo: $DATA not found (set SUPERLOC_SHARED_DATA to the folder holding kitti00-mini)" >&2
  exit 1
fi
rm -rf "$OUT" && mkdir -p "$OUT"
set -x
$BIN/superloc-import --kitti "$DATA" --poses "$DATA/gt_velodyne_tum.txt" --out "$OUT/kitti00-mini.rawlog"
$BIN/superloc-map --rawlog "$OUT/kitti00-mini.rawlog" --voxel 0.2 --out "$OUT/map.pcd"
# First GT pose (t x y z qx qy qz qw) perturbed by +0.5 m x, +0.5 m y, +0.2 m z, +5 deg yaw.
START=$(grep -v '^#' "$DATA/gt_velodyne_tum.txt" | head -1 | awk '{
  c = cos(0.0436332313); s = sin(0.0436332313);   # rotate q by 5 deg about z (left-multiply)
  qx = c*$5 - s*$6; qy = c*$6 + s*$5; qz = c*$7 + s*$8; qw = c*$8 - s*$7;
  printf "%.6f %.6f %.6f %.9f %.9f %.9f %.9f", $2+0.5, $3+0.5, $4+0.2, qx, qy, qz, qw }')
$BIN/superloc-localize ini/localize-kitti.ini --rawlog "$OUT/kitti00-mini.rawlog" \
    --map "$OUT/map.pcd" --initial-pose "$START" --out "$OUT/run"
$BIN/superloc-eval --est "$OUT/run/trajectory.tum" --gt "$DATA/gt_velodyne_tum.txt" \
    --json "$OUT/eval.json"
