#!/usr/bin/env bash
# `make fuzz SECONDS=N`: builds the libFuzzer targets with clang into BUILD_DIR (default build-fuzz/) and runs
# each for N seconds, one at a time at nice 19, from the committed seeds (fuzz/corpus/<target>/, copied into a
# working corpus BUILD_DIR/corpus/<target>/). Prints executions, coverage (cov: edges, ft: features) and findings
# per target; exits 1 if any target crashed, hung, leaked or tripped a sanitizer (the reproducer is kept in
# BUILD_DIR/findings/<target>/). Usage: scripts/fuzz.sh SECONDS [BUILD_DIR] [TARGETS...]
set -uo pipefail
SECS=${1:-60}
BUILD=${2:-build-fuzz}
shift 2 2>/dev/null || shift $#
TARGETS=${*:-"read_dds read_ktx2 read_exr read_npy read_png obj scene_json lut level_dds level_ktx2 material_json http_head"}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
CXX=${FUZZ_CXX:-clang++-14}
bash "$ROOT/scripts/install-deps.sh" --fuzz || exit 2
command -v "$CXX" >/dev/null || { echo "fuzz: $CXX not found (apt-get install clang-14 libclang-rt-14-dev)" >&2; exit 2; }

cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER="$CXX" \
  -DMSH_FUZZ=ON -DMSH_BUILD_TESTS=OFF -DMSH_BUILD_BENCH=OFF >/dev/null || exit 2
BUILD=$(cd "$BUILD" && pwd)
targets=()
for t in $TARGETS; do targets+=("fuzz_$t"); done
nice -n 19 cmake --build "$BUILD" -j "${JOBS:-2}" --target "${targets[@]}" msh_fuzz_seeds || exit 2

# Seeds: the committed ones, or regenerated when fuzz/corpus/ is absent.
SEEDS="$ROOT/fuzz/corpus"
if [ ! -d "$SEEDS" ]; then SEEDS="$BUILD/seeds"; "$BUILD/bin/msh_fuzz_seeds" "$SEEDS" || exit 2; fi

status=0
printf '%-12s %8s %12s %8s %8s %s\n' target seconds execs cov ft findings
for t in $TARGETS; do
  corpus="$BUILD/corpus/$t" findings="$BUILD/findings/$t" log="$BUILD/logs/$t.log"
  mkdir -p "$corpus" "$findings" "$(dirname "$log")"
  cp -n "$SEEDS/$t"/* "$corpus/" 2>/dev/null
  t0=$(date +%s)
  ( cd "$BUILD" && nice -n 19 "bin/fuzz_$t" -max_total_time="$SECS" -timeout=10 -rss_limit_mb=2048 \
      -max_len=65536 -print_final_stats=1 -artifact_prefix="$findings/" "$corpus" ) >"$log" 2>&1
  rc=$?
  elapsed=$(($(date +%s) - t0))
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*')
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*')
  n=$(find "$findings" -type f | wc -l)
  printf '%-12s %8s %12s %8s %8s %s\n' "$t" "$elapsed" "${execs:-?}" "${cov:-?}" "${ft:-?}" \
    "$n$([ $rc -ne 0 ] && echo " (exit $rc, see $log)")"
  [ $rc -ne 0 ] || [ "$n" -ne 0 ] && status=1
done
exit $status
