#!/usr/bin/env bash
# Active-fusion experiments (doc/results.md "Active fusion"): every method on the simulated worlds,
# evaluated with superloc-eval (ATE, map outlier % at 10 cm with the localized map at 5 cm).
#   scripts/active_fusion_experiments.sh BUILD_DIR SIM_DIR OUT_DIR [worlds] [methods] [-- --set ...]
# Sequences are simulated once into SIM_DIR/<world> (300-600 MB each: keep them out of the repo).
# Extra arguments after "--" go to every superloc-localize run (e.g. --set localization.use_imu=false).
set -euo pipefail
BUILD=${1:?build dir}; SIM=${2:?sim dir}; OUT=${3:?out dir}
WORLDS=${4:-"corridor cave multifloor office"}
METHODS=${5:-"icp ndt superloc passive eigen_remap"}
shift $(( $# < 5 ? $# : 5 ))
[[ ${1:-} == "--" ]] && shift
EXTRA=("$@")
ROOT=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$OUT"
for w in $WORLDS; do
  if [[ ! -f $SIM/$w/sequence.rawlog ]]; then
    "$BUILD/bin/superloc-sim" "$ROOT/ini/sim/$w.ini" --out "$SIM/$w"
  fi
  for m in $METHODS; do
    d=$OUT/$w/$m
    "$BUILD/bin/superloc-localize" "$ROOT/ini/localize.ini" --rawlog "$SIM/$w/sequence.rawlog" \
      --map "$SIM/$w/prior_map.pcd" --initial-pose-tum "$SIM/$w/gt_tum.txt" --method "$m" \
      --out "$d" --set run.localized_map_voxel=0.05 --quiet "${EXTRA[@]}"
    "$BUILD/bin/superloc-eval" --est "$d/trajectory.tum" --gt "$SIM/$w/gt_tum.txt" \
      --est-map "$d/localized_map.pcd" --gt-map "$SIM/$w/gt_map.ply" --frames "$d/frames.csv" \
      --json "$d/eval.json" > "$d/eval.txt"
  done
done
python3 "$ROOT/scripts/active_fusion_table.py" "$OUT"
