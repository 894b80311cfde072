#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz, clang-14 + libfuzzer-14-dev, ASan + UBSan) in
# ./build-fuzz and runs each for SECONDS, one after the other (one job each: the machine has two
# cores), seeded with cuts of the real files in the shared data folder.
#   scripts/fuzz.sh SECONDS [TARGET...]      TARGET in: pcd ply kitti_bin tum map_tiles ini cdr db3 mcap ros1
#                                             (default: all)
# Corpora grow in build-fuzz/corpus/<target>, crashes land in build-fuzz/artifacts/<target>/, the
# logs in build-fuzz/logs/<target>.log; a table of executions and coverage is printed at the end.
# Reproduce a crash: build-fuzz/fuzz/superloc-fuzz-<target> build-fuzz/artifacts/<target>/crash-...
set -euo pipefail
SECONDS_PER_TARGET=${1:?usage: scripts/fuzz.sh SECONDS [pcd ply kitti_bin tum map_tiles ini cdr db3 mcap ros1]}
shift
TARGETS=("$@")
[ ${#TARGETS[@]} -eq 0 ] && TARGETS=(pcd ply kitti_bin tum map_tiles ini cdr db3 mcap ros1)
cd "$(dirname "$0")/.."
ROOT=$(pwd)
DATA=${SUPERLOC_SHARED_DATA:-$ROOT/../shared/data}
B=build-fuzz

PKGS=(clang-14 libfuzzer-14-dev)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" != 0 ] && SUDO="sudo"
  $SUDO apt-get update
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi

if [ ! -f $B/build.ninja ]; then
  CC=clang-14 CXX=clang++-14 cmake -S . -B $B -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DSUPERLOC_FUZZ=ON -DSUPERLOC_BUILD_TESTS=OFF -DSUPERLOC_BUILD_BENCH=OFF \
    -DSUPERLOC_SHARED_DATA="$DATA"
fi
cmake --build $B -j "$(nproc)" --target "${TARGETS[@]/#/superloc-fuzz-}" superloc-fuzz-bag-seeds

[ -d "$DATA" ] || { echo "fuzz: $DATA not found (set SUPERLOC_SHARED_DATA)" >&2; exit 1; }
rm -rf $B/seeds
python3 scripts/fuzz_seeds.py "$DATA" "$ROOT" $B/seeds
$B/fuzz/superloc-fuzz-bag-seeds "$DATA" $B/seeds   # cdr db3 mcap ros1: small bags (C++ writers)
mkdir -p $B/logs

# ASan: report leaks too; UBSan: stop at the first report (also compiled with no recovery).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
status=0
summary=()
for t in "${TARGETS[@]}"; do
  mkdir -p $B/corpus/$t $B/artifacts/$t
  echo "== $t: ${SECONDS_PER_TARGET} s"
  rc=0
  max_len=8192
  case $t in db3|mcap|ros1) max_len=65536 ;; esac   # a bag's smallest real file is a few kB
  $B/fuzz/superloc-fuzz-$t $B/corpus/$t $B/seeds/$t \
    -max_total_time="$SECONDS_PER_TARGET" -max_len=$max_len -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix=$B/artifacts/$t/ > $B/logs/$t.log 2>&1 || rc=$?
  execs=$(awk '/stat::number_of_executed_units/ {print $NF}' $B/logs/$t.log)
  speed=$(awk '/stat::average_exec_per_sec/ {print $NF}' $B/logs/$t.log)
  last=$(grep -E '^#[0-9]+' $B/logs/$t.log | tail -1 || true)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<< "$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<< "$last")
  corpus=$(ls $B/corpus/$t | wc -l)
  crashes=$(ls $B/artifacts/$t | wc -l)
  [ "$rc" != 0 ] && status=1 && tail -40 $B/logs/$t.log
  summary+=("$(printf '%-10s %5s s %12s %8s %7s %7s %7s %8s' "$t" "$SECONDS_PER_TARGET" \
    "${execs:-?}" "${speed:-?}" "${cov:-?}" "${ft:-?}" "$corpus" "$crashes")")
done
echo
printf '%-10s %7s %12s %8s %7s %7s %7s %8s\n' target time execs exec/s cov ft corpus findings
printf '%s\n' "${summary[@]}"
exit $status
