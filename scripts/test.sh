#!/usr/bin/env bash
# The whole test suite: set-up, build, every test through ctest; then the same
# tests built with AddressSanitizer and UndefinedBehaviorSanitizer.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GRAPEBENCH_BUILD_DIR:-$here/build}"
"$here/scripts/setup.sh" "$build"
(cd "$build" && ctest --output-on-failure --parallel "$(nproc)" --timeout 900)
echo "== regression gate: the default suite against its committed baseline"
(cd "$here" && "$build/bench/grapebench" run scenes/default.yaml --out "$build/gate" --no-resume --quiet >/dev/null &&
  "$build/bench/grapebench" check "$build/gate/default" --baseline results/baseline/default.json)
if [ "${GRAPEBENCH_SKIP_SANITIZERS:-0}" != 1 ]; then
  echo "== the same tests under ASan/UBSan"
  CMAKE_BUILD_TYPE=RelWithDebInfo "$here/scripts/setup.sh" "$build-asan" \
    -DGRAPEBENCH_SANITIZE=ON -DGRAPEBENCH_BUILD_BENCHMARKS=OFF
  (cd "$build-asan" && ctest --output-on-failure --parallel "$(nproc)" --timeout 1800)
fi
