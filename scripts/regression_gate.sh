#!/usr/bin/env bash
# The regression gates: one small scene per protocol, run and checked by `grapebench
# check` against its committed baseline (results/baseline/<name>.json, with the
# tolerances measured for it: docs/harness.md, "Regression gates"). Every gate runs
# even when one fails; the exit code is the worst (1 a regression, 2 bad input).
# Usage: scripts/regression_gate.sh [build-dir] [gate...]
#   gates: default (multi_view, seed 000), seed001_gate (stereo_pair), seed002_gate
#   (multi_view with the bottom view and perimeters), seed003_gate (single_frame),
#   seed004_gate (classification). GRAPEBENCH_GATE_OUT sets the output folder.
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-${GRAPEBENCH_BUILD_DIR:-$here/build}}"
shift || true
declare -A scene=(
  [default]=scenes/default.yaml
  [seed001_gate]=scenes/gate/seed001_gate.yaml
  [seed002_gate]=scenes/gate/seed002_gate.yaml
  [seed003_gate]=scenes/gate/seed003_gate.yaml
  [seed004_gate]=scenes/gate/seed004_gate.yaml
)
gates=("$@")
((${#gates[@]})) || gates=(default seed001_gate seed002_gate seed003_gate seed004_gate)
out="${GRAPEBENCH_GATE_OUT:-$build/gate}"
worst=0
for g in "${gates[@]}"; do
  if [ -z "${scene[$g]:-}" ]; then
    echo "regression gate: no gate named '$g' (one of: ${!scene[*]})" >&2
    exit 2
  fi
  t0=$(date +%s)
  rc=0
  (cd "$here" && "$build/bench/grapebench" run "${scene[$g]}" --out "$out" --no-resume --quiet >"$out.$g.log" 2>&1) || rc=$?
  if [ "$rc" -eq 0 ]; then
    "$build/bench/grapebench" check "$out/$g" --baseline "$here/results/baseline/$g.json" || rc=$?
  else
    echo "regression gate $g: the run failed (exit $rc):"; tail -20 "$out.$g.log"
    rc=2
  fi
  echo "regression gate $g: exit $rc, $(( $(date +%s) - t0 )) s"
  ((rc > worst)) && worst=$rc
done
exit "$worst"
