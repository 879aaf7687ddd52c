#!/usr/bin/env bash
# The whole test suite: set-up, build, every test through ctest, the regression gates
# (one small scene per protocol against its committed baseline) and the speed gate;
# then the clang AddressSanitizer + UndefinedBehaviorSanitizer build: every unit test,
# the regression gates' reduced end-to-end scenes and a short run of every libFuzzer
# target (tests/fuzz). The long end-to-end tests (ctest label `e2e`) run in the
# Release stage only: under the sanitizers they cost 3-4x and reach no code that the
# gates' scenes do not. The unit tests labelled `sibling` run in the Release stage only
# too: a sibling test runs their code under the sanitizers (tests/CMakeLists.txt;
# docs/harness.md, "CI's time").
# At the end, whatever the outcome: a table of stage times and the 15 slowest tests.
#
# Usage: scripts/test.sh           the whole suite (what .ci/run runs)
#        scripts/test.sh --quick   the developer loop: Release build and the unit tests
#                                  (labels `unit` and `sibling`), no gates, no sanitizers
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GRAPEBENCH_BUILD_DIR:-$here/build}"
quick=0
case "${1:-}" in
  --quick) quick=1 ;;
  "") ;;
  *) echo "usage: scripts/test.sh [--quick]" >&2; exit 2 ;;
esac

times="$(mktemp -d)"
start_all=$(date +%s)
stage_start=$start_all
stage_name=""
stage() {  # close the running stage (if any), open the next
  local now; now=$(date +%s)
  [ -z "$stage_name" ] || printf '%s\t%d\n' "$stage_name" $((now - stage_start)) >>"$times/stages.tsv"
  stage_name="$1"; stage_start=$now
  [ -z "$1" ] || echo "== $1"
}
summary() {
  local rc=$?
  stage ""
  /usr/bin/python3 "$here/scripts/test_times.py" "$times/stages.tsv" "$times"/*.xml || true
  echo "scripts/test.sh: total $(( $(date +%s) - start_all )) s, exit $rc"
  rm -rf "$times"
}
trap summary EXIT

stage "set-up and Release build"
"$here/scripts/setup.sh" "$build"
ctest_args=(--output-on-failure --parallel "$(nproc)")
if ((quick)); then
  stage "unit tests (Release, labels unit and sibling)"
  (cd "$build" && ctest "${ctest_args[@]}" --timeout 600 -L "^(unit|sibling)$" --output-junit "$times/release.xml")
  exit 0
fi
stage "every test (Release)"
(cd "$build" && ctest "${ctest_args[@]}" --timeout 900 --output-junit "$times/release.xml")
stage "regression gates (Release)"
"$here/scripts/regression_gate.sh" "$build"
stage "speed gate"
"$here/scripts/speed_gate.sh" "$build"
if [ "${GRAPEBENCH_SKIP_SANITIZERS:-0}" != 1 ]; then
  asan="$build-asan-clang"
  stage "sanitizer build (clang, ASan + UBSan)"
  CC=clang CXX=clang++ CMAKE_BUILD_TYPE=RelWithDebInfo "$here/scripts/setup.sh" "$asan" \
    -DGRAPEBENCH_FUZZ=ON -DGRAPEBENCH_FUZZ_SECONDS="${GRAPEBENCH_FUZZ_SECONDS:-20}" -DGRAPEBENCH_BUILD_BENCHMARKS=OFF
  stage "unit tests and fuzz targets (ASan + UBSan)"
  (cd "$asan" && ctest "${ctest_args[@]}" --timeout 1800 -LE "^(e2e|sibling)$" --output-junit "$times/asan.xml")
  stage "regression gates (ASan + UBSan: the reduced end-to-end runs)"
  # The protocols' small gates; not the default suite, whose PB solvers took 578 s
  # under the sanitizers and the fuzzer's coverage (7 s in Release).
  LSAN_OPTIONS="suppressions=$here/tests/lsan.supp" "$here/scripts/regression_gate.sh" "$asan" \
    seed001_gate seed002_gate seed003_gate seed004_gate
fi
