#!/usr/bin/env bash
# Each regression gate against a deliberate break of its protocol: a git worktree of
# HEAD (build/breaks/src), one one-line change to the protocol's algorithm at a time,
# grapebench rebuilt (ccache: only the changed unity batch compiles), the gate run;
# a break the gate lets through is a failure of this script. Not part of CI (each
# break rebuilds); its output is in docs/harness.md, "Regression gates".
# Usage: scripts/gate_breaks.sh [break...]   (names below; default all)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dir="${GRAPEBENCH_BREAKS_DIR:-$here/build/breaks}"
# name | gate | file | sed expression (one line changed) | what it breaks
breaks=(
  "cut_point_6px|seed001_gate|algorithms/stereo/cutting_point_detection.cpp|s/d.y = 0.5 \* (best.y1 + best.y2);/d.y = 0.5 * (best.y1 + best.y2) + 6;/|seed 001: the cutting point 6 px below the stalk line's midpoint"
  "perimeter_5pct|seed002_gate|algorithms/size/section_perimeters.cpp|s/s.perimeter(k) = spline_length(closed_hobby_spline(clean, p.tension));/s.perimeter(k) = 1.05 * spline_length(closed_hobby_spline(clean, p.tension));/|seed 002: every section perimeter 5 % long"
  "percentile_low|seed003_gate|algorithms/size/percentile_box.cpp|s/b.minimum(k) = percentile(v, p.alpha);/b.minimum(k) = percentile(v, p.alpha + 0.1);/|seed 003: the box's low percentile at alpha + 10 %"
  "saliency_surface|seed004_gate|algorithms/classification/saliency_features.cpp|s/return {ev\[0\], ev\[2\] - ev\[1\], ev\[1\] - ev\[0\]};/return {ev[0], ev[2] - ev[1], 0.0};/|seed 004: the surface-ness saliency (lambda1 - lambda2) always 0"
)
want=("$@")
mkdir -p "$dir"
src="$dir/src"
if [ ! -e "$src/.git" ]; then
  git -C "$here" worktree add --detach "$src" HEAD >/dev/null
fi
git -C "$src" checkout --quiet --detach "$(git -C "$here" rev-parse HEAD)"
git -C "$src" checkout --quiet -- .
status=0
printf '%-18s %-14s %-6s %s\n' break gate exit verdict
for b in "${breaks[@]}"; do
  IFS='|' read -r name gate file expr what <<<"$b"
  if ((${#want[@]})) && [[ ! " ${want[*]} " == *" $name "* ]]; then continue; fi
  cp "$src/$file" "$dir/orig"
  sed -i "$expr" "$src/$file"
  if cmp -s "$src/$file" "$dir/orig"; then
    echo "gate_breaks: the break $name changed nothing in $file (the code moved?)" >&2
    exit 2
  fi
  bash "$src/scripts/setup.sh" "$src/build" -DGRAPEBENCH_BUILD_TESTS=OFF -DGRAPEBENCH_BUILD_BENCHMARKS=OFF >"$dir/$name.build.log" 2>&1 ||
    { echo "gate_breaks: $name does not build; see $dir/$name.build.log" >&2; cp "$dir/orig" "$src/$file"; exit 2; }
  rc=0
  GRAPEBENCH_GATE_OUT="$dir/gate_$name" "$src/scripts/regression_gate.sh" "$src/build" "$gate" >"$dir/$name.gate.log" 2>&1 || rc=$?
  cp "$dir/orig" "$src/$file"
  verdict="caught"
  [ "$rc" -eq 1 ] || { verdict="NOT CAUGHT"; status=1; }
  printf '%-18s %-14s %-6s %s (%s)\n' "$name" "$gate" "$rc" "$verdict" "$what"
  grep -E '^(WORSE|MISSING)' "$dir/$name.gate.log" | head -4 | sed 's/^/    /'
  n=$(grep -cE '^(WORSE|MISSING)' "$dir/$name.gate.log" || true)
  echo "    ($n rows worse or missing)"
done
exit "$status"
