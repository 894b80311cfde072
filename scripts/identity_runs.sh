#!/usr/bin/env bash
# A refactoring's regression harness: the same 18 localizer runs with two builds, then every
# output compared (frames.csv but its ms_* times, trajectory.tum, trajectory_cov.txt) by
# scripts/identity_compare.py. The runs cover the six methods, no IMU, --initial-pose auto (the
# global search and tracked candidates), the README's KITTI split and corridor, a 70 s cave and
# the office world searched from no pose.
#   scripts/identity_runs.sh BIN_DIR DATA_DIR OUT_DIR
#   (e.g. BIN_DIR = a copy of build/bin before the change, then build/bin after it)
#   scripts/identity_compare.py OUT_BEFORE OUT_AFTER
# DATA_DIR holds the simulated and imported inputs, made once by the first call (with BIN_DIR's
# tools; ~1 GB); ../shared/data (or SUPERLOC_SHARED_DATA) must hold kitti00-mini.
set -euo pipefail
BIN=${1:?bin dir}; D=${2:?data dir}; OUT=${3:?out dir}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
KITTI=${SUPERLOC_SHARED_DATA:-$ROOT/../shared/data}/kitti00-mini
mkdir -p "$D" "$OUT"
if [[ ! -f $D/kitti-start.txt ]]; then
  "$BIN/superloc-import" --kitti "$KITTI" --poses "$KITTI/gt_velodyne_tum.txt" --out "$D/kitti.rawlog"
  "$BIN/superloc-map" --rawlog "$D/kitti.rawlog" --voxel 0.2 --set rawlog.scans=even --out "$D/kitti-even.pcd"
  # The README demo's start: the first odd scan's pose moved 0.5 m / 0.5 m / 0.2 m and 5 deg.
  grep -v '^#' "$KITTI/gt_velodyne_tum.txt" | sed -n 2p | awk '{
    c = cos(0.0436332313); s = sin(0.0436332313);
    qx = c*$5 - s*$6; qy = c*$6 + s*$5; qz = c*$7 + s*$8; qw = c*$8 - s*$7;
    printf "%.6f %.6f %.6f %.9f %.9f %.9f %.9f", $2+0.5, $3+0.5, $4+0.2, qx, qy, qz, qw }' > "$D/kitti-start.txt"
fi
[[ -f $D/corridor/sequence.rawlog ]] || "$BIN/superloc-sim" "$ROOT/ini/sim/corridor.ini" --out "$D/corridor" \
  --set corridor.length=150 --set corridor.recesses=0 --set sim.duration=30 --set lidar.preset=../sensors/vlp16.ini
[[ -f $D/cave/sequence.rawlog ]] || "$BIN/superloc-sim" "$ROOT/ini/sim/cave.ini" --out "$D/cave" --seed 1
[[ -f $D/office/sequence.rawlog ]] || "$BIN/superloc-sim" "$ROOT/ini/sim/office.ini" --out "$D/office" --seed 1

run() {  # name [--ini FILE] args...
  local name=$1; shift
  local ini=$ROOT/ini/localize.ini
  if [[ ${1:-} == --ini ]]; then ini=$2; shift 2; fi
  if "$BIN/superloc-localize" "$ini" --quiet "$@" --out "$OUT/$name" > "$OUT/$name.log" 2>&1
  then echo "$name: ok"; else echo "$name: exit $?"; fi
}
T=$ROOT/rawlogs
TINY=(--rawlog "$T/office-tiny.rawlog" --map "$T/office-tiny-map.pcd")
for m in superloc icp ndt passive superloc_paper eigen_remap; do
  run "tiny-$m" "${TINY[@]}" --initial-pose-tum "$T/office-tiny-gt.tum" --method $m
done
run tiny-noimu "${TINY[@]}" --initial-pose-tum "$T/office-tiny-gt.tum" --set localization.use_imu=false
run tiny-auto "${TINY[@]}" --initial-pose auto
K=(--rawlog "$D/kitti.rawlog" --set rawlog.scans=odd --map "$D/kitti-even.pcd" --set features.deskew=false)
run kitti-voxel "${K[@]}" --initial-pose "$(cat "$D/kitti-start.txt")" --set association.kind=voxel \
  --set localization.rounds=10
run kitti-nearest "${K[@]}" --initial-pose "$(cat "$D/kitti-start.txt")"
run kitti-auto "${K[@]}" --initial-pose auto
# The driving INI (tests/e2e's perturbed start): the start check ties and takes a rival, then searches.
run kitti-ini --ini "$ROOT/ini/localize-kitti.ini" "${K[@]}" --initial-pose "$(cat "$D/kitti-start.txt")"
C=(--rawlog "$D/corridor/sequence.rawlog" --map "$D/corridor/prior_map.pcd" --initial-pose-tum "$D/corridor/gt_tum.txt")
run corr-superloc "${C[@]}"
run corr-ndt "${C[@]}" --method ndt
run corr-noimu "${C[@]}" --set localization.use_imu=false
run cave --rawlog "$D/cave/sequence.rawlog" --map "$D/cave/prior_map.pcd" --initial-pose-tum "$D/cave/gt_tum.txt"
for imu in true false; do
  run "office-auto-imu-$imu" --rawlog "$D/office/sequence.rawlog" --map "$D/office/prior_map.pcd" \
    --initial-pose auto --set localization.use_imu=$imu --set rawlog.scans=0:150
done
