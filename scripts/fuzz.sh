#!/usr/bin/env bash
# Fuzzes every reader of outside input (tests/fuzz/) for the given seconds each
# (default 600), under ASan and UBSan, and reports executions per second and
# coverage per target. Findings (crash-*, timeout-*, leak-*) are left in
# build-asan-clang/findings/<target>/; exit 1 when any target found something.
# Usage: scripts/fuzz.sh [seconds] [target...]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-600}"
shift || true
# The sanitizer build of scripts/test.sh, which holds the fuzz targets: one build.
build="${GRAPEBENCH_FUZZ_BUILD_DIR:-${GRAPEBENCH_BUILD_DIR:-$here/build}-asan-clang}"
CC=clang CXX=clang++ CMAKE_BUILD_TYPE=RelWithDebInfo "$here/scripts/setup.sh" "$build" \
  -DGRAPEBENCH_FUZZ=ON -DGRAPEBENCH_BUILD_BENCHMARKS=OFF
targets=("$@")
if ((${#targets[@]} == 0)); then
  targets=(scene case_file baseline bench_json external_answer cloud_file)
fi
declare -A seeds=(
  [scene]="$here/scenes $here/tests/bench/data $here/tests/fuzz/corpus/scene"
  [case_file]="$here/tests/fuzz/corpus/case_file"
  [baseline]="$here/results/baseline $here/tests/fuzz/corpus/baseline"
  [bench_json]="$here/tests/fuzz/corpus/bench_json"
  [external_answer]="$here/tests/fuzz/corpus/external_answer"
  [cloud_file]="$here/tests/fuzz/corpus/cloud_file"
)
declare -A dicts=([scene]=yaml [cloud_file]=cloud [case_file]=json [baseline]=json [bench_json]=json
  [external_answer]=json)
export LSAN_OPTIONS="suppressions=$here/tests/lsan.supp"
status=0
printf '%-16s %10s %10s %8s %8s  %s\n' target runs exec/s cov ft findings
for t in "${targets[@]}"; do
  corpus="$build/corpus/$t" findings="$build/findings/$t"
  mkdir -p "$corpus" "$findings"
  log="$build/findings/$t.log"
  # shellcheck disable=SC2086
  if ! "$build/tests/fuzz/${t}_fuzz" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 \
      -dict="$here/tests/fuzz/dict/${dicts[$t]}.dict" -print_final_stats=1 -artifact_prefix="$findings/" "$corpus" ${seeds[$t]} >"$log" 2>&1; then
    status=1
  fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  rate=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo 0)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo 0)
  found=$(find "$findings" -maxdepth 1 -type f | wc -l)
  ((found == 0)) || status=1
  printf '%-16s %10s %10s %8s %8s  %s\n' "$t" "$runs" "$rate" "$cov" "$ft" "$found (log: $log)"
done
exit $status
