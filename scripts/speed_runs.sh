#!/usr/bin/env bash
# What a user pays (issue 34's tables in doc/results.md): the suite ini/bench/speed.ini
# (superloc-localize with the default INI on seed 1 of the five simulated worlds and on the three
# real splits of real.ini) run by superloc-bench pinned to one core, one run at a time. Prints one
# line per run: median CPU ms a tracked frame (summary.json), the stage medians, the first
# frame's CPU ms, mean rounds, ATE against the rawlog's GT and the health counts.
#   scripts/speed_runs.sh BIN_DIR DATA_DIR OUT_DIR [CORE] [RUNS...]
#   (RUNS: sequences of speed.ini, default all of them)
# DATA_DIR holds the simulated and imported inputs (the suite's data/, ~2 GB), made once by the
# first call with BIN_DIR's tools and shared by later calls. Compare two builds by alternating
# calls (this machine's noise is +-10-15 %), e.g.
#   for i in 1 2; do for b in before after; do scripts/speed_runs.sh /tmp/$b /tmp/sd /tmp/o-$b-$i; done; done
set -euo pipefail
BIN=$(cd "${1:?bin dir}" && pwd); D=${2:?data dir}; OUT=${3:?out dir}; CORE=${4:-1}
shift $(( $# < 4 ? $# : 4 ))
ROOT=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$D" "$OUT"
ln -sfn "$(cd "$D" && pwd)" "$OUT/data"
seqs=()
[[ $# -gt 0 ]] && seqs=(--sequences "$*")
taskset -c "$CORE" "$BIN/superloc-bench" "$ROOT/ini/bench/speed.ini" --jobs 1 --tools "$BIN" --out "$OUT" \
  "${seqs[@]}" > "$OUT/bench.log" 2>&1 || { echo "superloc-bench failed, see $OUT/bench.log"; exit 1; }
python3 - "$OUT" "$@" <<'PY'
import csv, json, os, sys
out = sys.argv[1]
# The runs asked for, else every run of the suite (results.json, in the suite's order).
names = sys.argv[2:] or [r["sequence"] for r in json.load(open(os.path.join(out, "results.json")))["runs"]]
for name in names:
    d = os.path.join(out, "runs", name, "superloc")
    s = json.load(open(os.path.join(d, "summary.json")))
    rows = list(csv.DictReader(open(os.path.join(d, "frames.csv"))))
    st, h, ate = s["stage_ms_median"], s["frames_health"], s["ate_rmse_vs_rawlog_gt"]
    rounds = sum(int(r["rounds"]) for r in rows) / max(1, len(rows))
    print(f"{name:10s} cpu median {s['cpu_ms_per_frame_median']:7.2f} ms | preprocess {st['preprocess']:.2f} "
          f"associate {st['associate']:.2f} risk {st['risk']:.2f} solve {st['solve']:.2f} | first frame "
          f"{float(rows[0]['ms_total_cpu']):6.1f} ms | rounds {rounds:.2f} | ATE "
          f"{'-' if ate is None else f'{ate:.4f}'} m | ok/degraded/lost {h['ok']}/{h['degraded']}/{h['lost']}")
PY
