#!/usr/bin/env bash
# Installs the dependencies, builds, and runs the main job on two bundled demos:
# 1. KITTI 00 (first 16 scans, ../shared/data/kitti00-mini) -> rawlog -> prior map from the even
#    scans -> localize the odd scans (never in the map) from a start perturbed by (0.5 m, 0.5 m,
#    0.2 m, 5 deg yaw) with the voxel-map association (doc/map.md) -> evaluate against ground truth.
# 2. Active fusion: a simulated 150 m corridor with nothing along its axis (VLP-16, IMU and a
#    drifting second odometry, 30 s) localized with icp (no second odometry), passive (the
#    second odometry on every axis) and superloc (only on the axes the risk flags), each with and
#    without the IMU, evaluated against the simulator's ground truth.
# Outputs in ./out/demo.
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
$BIN/superloc-map --rawlog "$OUT/kitti00-mini.rawlog" --voxel 0.2 --set rawlog.scans=even \
    --out "$OUT/map-even.pcd"
# GT pose of the first odd scan (t x y z qx qy qz qw) perturbed by +0.5 m x, +0.5 m y, +0.2 m z,
# +5 deg yaw.
START=$(grep -v '^#' "$DATA/gt_velodyne_tum.txt" | sed -n 2p | awk '{
  c = cos(0.0436332313); s = sin(0.0436332313);   # rotate q by 5 deg about z (left-multiply)
  qx = c*$5 - s*$6; qy = c*$6 + s*$5; qz = c*$7 + s*$8; qw = c*$8 - s*$7;
  printf "%.6f %.6f %.6f %.9f %.9f %.9f %.9f", $2+0.5, $3+0.5, $4+0.2, qx, qy, qz, qw }')
$BIN/superloc-localize ini/localize.ini --rawlog "$OUT/kitti00-mini.rawlog" --set rawlog.scans=odd \
    --map "$OUT/map-even.pcd" --initial-pose "$START" --set features.deskew=false \
    --set association.kind=voxel --set localization.rounds=10 --out "$OUT/run"
$BIN/superloc-eval --est "$OUT/run/trajectory.tum" --gt "$DATA/gt_velodyne_tum.txt" \
    --json "$OUT/eval.json"

# 2. Active fusion on a featureless corridor (~30 s).
$BIN/superloc-sim ini/sim/corridor.ini --out "$OUT/corridor" --set corridor.length=150 \
    --set corridor.recesses=0 --set sim.duration=30 --set lidar.preset=../sensors/vlp16.ini
for imu in true false; do
  for m in icp passive superloc; do
    R="$OUT/corridor-$m-imu-$imu"
    $BIN/superloc-localize ini/localize.ini --rawlog "$OUT/corridor/sequence.rawlog" \
        --map "$OUT/corridor/prior_map.pcd" --initial-pose-tum "$OUT/corridor/gt_tum.txt" \
        --method $m --set localization.use_imu=$imu --out "$R" --quiet
    $BIN/superloc-eval --est "$R/trajectory.tum" --gt "$OUT/corridor/gt_tum.txt" \
        --json "$R/eval.json" > "$R/eval.txt"
  done
done
set +x
ate() {  # ATE translation RMSE [m] of a superloc-eval --json file
  python3 -c 'import json, sys; v = json.load(open(sys.argv[1]))["ate"]["trans_m"]["rmse"]
print("n/a" if v is None else "%.3f" % v)' "$1"
}
echo
echo "kitti00-mini odd scans in the even scans' map (perturbed start), ATE RMSE [m]: $(ate "$OUT/eval.json")"
for imu in true false; do
  echo "featureless corridor, IMU $imu, ATE RMSE [m]: icp $(ate "$OUT/corridor-icp-imu-$imu/eval.json")," \
       "passive $(ate "$OUT/corridor-passive-imu-$imu/eval.json"), superloc $(ate "$OUT/corridor-superloc-imu-$imu/eval.json")"
done
echo "(frames.csv in $OUT/corridor-superloc-imu-false: degenerate = x where the estimate is weak along x (est_sigma_x above 5 cm), prior_w_x is the odom_alt weight it got; gamma_x is the paper's scan-only risk)"
