#!/usr/bin/env bash
# What a user pays (issue 34's tables in doc/results.md): superloc-localize with the default INI
# on one core, on seed 1 of the five simulated worlds and on the three real splits (odd scans in
# the map of the even scans: campus-ouster; kitti00-mini at the LiDAR-consistent reference poses;
# kitti00-mini at KITTI's ground truth, whose map is warped), from the reference pose. Prints one
# line per run: median CPU ms a tracked frame (summary.json), the stage medians, the first
# frame's CPU ms, mean rounds, ATE against the rawlog's GT and the health counts.
#   scripts/speed_runs.sh BIN_DIR DATA_DIR OUT_DIR [CORE] [RUNS...]
#   (RUNS: any of corridor cave multifloor openfield office campus kitti-ref kitti-gt; default all)
# DATA_DIR holds the simulated and imported inputs, made once by the first call with BIN_DIR's
# tools (~2 GB). Extra superloc-localize arguments: SPEED_ARGS="--set a.b=c ...".
# Compare two builds by alternating calls (this machine's noise is +-10-15 %), e.g.
#   for i in 1 2; do for b in before after; do scripts/speed_runs.sh /tmp/$b /tmp/sd /tmp/o-$b-$i; done; done
set -euo pipefail
BIN=$(cd "${1:?bin dir}" && pwd); D=${2:?data dir}; OUT=${3:?out dir}; CORE=${4:-1}
shift $(( $# < 4 ? $# : 4 ))
RUNS=${*:-corridor cave multifloor openfield office campus kitti-ref kitti-gt}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
SD=${SUPERLOC_SHARED_DATA:-$ROOT/../shared/data}
mkdir -p "$D" "$OUT"
D=$(cd "$D" && pwd)

# Inputs, made once.
for w in corridor cave multifloor openfield office; do
  [[ -f $D/$w/sequence.rawlog ]] || "$BIN/superloc-sim" "$ROOT/ini/sim/$w.ini" --seed 1 --out "$D/$w" > "$D/$w.log"
done
split() {  # name, import args, poses, map voxel
  local name=$1 poses=$3 voxel=$4
  [[ -f $D/$name/map.pcd ]] && return
  mkdir -p "$D/$name"
  # shellcheck disable=SC2086
  "$BIN/superloc-import" $2 --poses "$poses" --out "$D/$name/all.rawlog" > "$D/$name/import.log"
  "$BIN/superloc-map" --rawlog "$D/$name/all.rawlog" --voxel "$voxel" --set rawlog.scans=even \
    --out "$D/$name/map.pcd" > "$D/$name/map.log"
  cp "$poses" "$D/$name/gt.tum"
}
split campus "--pcd-dir $SD/campus-ouster/scans" "$SD/campus-ouster/gt_tum.txt" 0.1
split kitti-ref "--kitti $SD/kitti00-mini" "$SD/kitti00-mini/ref_lidar_tum.txt" 0.1
split kitti-gt "--kitti $SD/kitti00-mini" "$SD/kitti00-mini/gt_velodyne_tum.txt" 0.1

for r in $RUNS; do
  case $r in
    campus | kitti-ref | kitti-gt)
      args=(--rawlog "$D/$r/all.rawlog" --map "$D/$r/map.pcd" --initial-pose-tum "$D/$r/gt.tum"
            --set rawlog.scans=odd --set features.deskew=false) ;;
    *)
      args=(--rawlog "$D/$r/sequence.rawlog" --map "$D/$r/prior_map.pcd" --initial-pose-tum "$D/$r/gt_tum.txt") ;;
  esac
  # shellcheck disable=SC2086
  taskset -c "$CORE" "$BIN/superloc-localize" "$ROOT/ini/localize.ini" "${args[@]}" --quiet \
    --out "$OUT/$r" ${SPEED_ARGS:-} > "$OUT/$r.log" 2>&1 || { echo "$r: failed, see $OUT/$r.log"; continue; }
  python3 - "$OUT/$r" "$r" <<'EOF'
import csv, json, sys
d, name = sys.argv[1], sys.argv[2]
s = json.load(open(d + "/summary.json"))
rows = list(csv.DictReader(open(d + "/frames.csv")))
st = s["stage_ms_median"]
rounds = sum(int(r["rounds"]) for r in rows) / max(1, len(rows))
h = s["frames_health"]
ate = s["ate_rmse_vs_rawlog_gt"]
print(f"{name:10s} cpu median {s['cpu_ms_per_frame_median']:7.2f} ms | preprocess {st['preprocess']:.2f} "
      f"associate {st['associate']:.2f} risk {st['risk']:.2f} solve {st['solve']:.2f} | first frame "
      f"{float(rows[0]['ms_total_cpu']):6.1f} ms | rounds {rounds:.2f} | ATE "
      f"{'-' if ate is None else f'{ate:.4f}'} m | ok/degraded/lost {h['ok']}/{h['degraded']}/{h['lost']}")
EOF
done
