#!/usr/bin/env bash
# The whole test suite: set-up, build, every test through ctest, the regression gate
# and the speed gate; then the same tests built by clang with AddressSanitizer and
# UndefinedBehaviorSanitizer, with a short run of every libFuzzer target (tests/fuzz).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GRAPEBENCH_BUILD_DIR:-$here/build}"
"$here/scripts/setup.sh" "$build"
(cd "$build" && ctest --output-on-failure --parallel "$(nproc)" --timeout 900)
echo "== regression gate: the default suite against its committed baseline"
(cd "$here" && "$build/bench/grapebench" run scenes/default.yaml --out "$build/gate" --no-resume --quiet >/dev/null &&
  "$build/bench/grapebench" check "$build/gate/default" --baseline results/baseline/default.json)
echo "== speed gate: in-run ratios against results/baseline/speed_gate.json"
"$here/scripts/speed_gate.sh" "$build"
if [ "${GRAPEBENCH_SKIP_SANITIZERS:-0}" != 1 ]; then
  echo "== the same tests under ASan/UBSan (clang), and each fuzz target for ${GRAPEBENCH_FUZZ_SECONDS:-20} s"
  CC=clang CXX=clang++ CMAKE_BUILD_TYPE=RelWithDebInfo "$here/scripts/setup.sh" "$build-asan-clang" \
    -DGRAPEBENCH_FUZZ=ON -DGRAPEBENCH_FUZZ_SECONDS="${GRAPEBENCH_FUZZ_SECONDS:-20}" -DGRAPEBENCH_BUILD_BENCHMARKS=OFF
  (cd "$build-asan-clang" && ctest --output-on-failure --parallel "$(nproc)" --timeout 1800)
fi
