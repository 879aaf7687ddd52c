#!/usr/bin/env bash
# Speed across commits: builds commits A and B (git worktrees under the build folder,
# Release, ccache), then runs each Google Benchmark executable of both builds in
# alternation, ROUNDS times (A B A B ...: both see the same machine state), and prints
# per benchmark the two medians over every repetition, the ratio B/A, the range of
# the per-round ratios and `grapebench compare-bench`'s verdict (SLOWER only when the
# ratio of medians exceeds 1 + THRESHOLD and the Mann-Whitney U test gives p < 0.05).
# A benchmark is called faster or slower only where every round's ratio is beyond
# 1 -/+ THRESHOLD (the spread column); otherwise "~".
#
# Usage: scripts/compare_commits.sh A B [filter] [rounds] [repetitions]
#   filter       Google Benchmark regex (default: the speed gate's benchmarks)
#   rounds       alternations of A and B (default 5)
#   repetitions  --benchmark_repetitions per run (default 3)
# Environment: GRAPEBENCH_COMPARE_DIR (default build/compare), THRESHOLD (0.05).
# Exit: 0, or 1 when compare-bench flags a slowdown of B, 2 on bad input.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if (($# < 2)); then
  sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
a="$1" b="$2"
filter="${3:-kinect_v2_turntable|d435_robot_pass|ideal_turntable12|^BM_(CH|VoxelGrid|ICP)_}"
rounds="${4:-5}" reps="${5:-3}"
threshold="${THRESHOLD:-0.05}"
dir="${GRAPEBENCH_COMPARE_DIR:-$here/build/compare}"
mkdir -p "$dir"
perf=(grapebench_sensor_perf grapebench_open3d_perf grapebench_perf grapebench_estimator_perf
      grapebench_frame_perf grapebench_stereo_perf grapebench_classification_perf)

declare -A sha
for side in a b; do
  rev="${!side}"
  sha[$side]="$(git -C "$here" rev-parse --verify --quiet "$rev^{commit}")" ||
    { echo "compare_commits: '$rev' is not a commit of $here" >&2; exit 2; }
  wt="$dir/src_$side"
  if [ ! -d "$wt/.git" ] && [ ! -f "$wt/.git" ]; then
    git -C "$here" worktree add --detach "$wt" "${sha[$side]}" >/dev/null
  else
    git -C "$wt" checkout --quiet --detach "${sha[$side]}"
  fi
  echo "== building $side = ${sha[$side]:0:10} ($(git -C "$here" log -1 --format=%s "${sha[$side]}" | cut -c1-60))"
  # The commit's own set-up script, so each side builds as it did at the time.
  # The build inside the worktree, as in a checkout: the compiler then sees `-I ..`
  # and ccache serves the objects any checkout built (a sibling folder missed them all).
  bash "$wt/scripts/setup.sh" "$wt/build" -DGRAPEBENCH_BUILD_TESTS=OFF >"$dir/build_$side.log" 2>&1 ||
    { echo "compare_commits: the build of $side failed; see $dir/build_$side.log" >&2; exit 2; }
done

gb="$dir/src_b/build/bench/grapebench"
rm -rf "$dir/runs"; mkdir -p "$dir/runs"
ran=()
for exe in "${perf[@]}"; do
  [ -x "$dir/src_a/build/bench/$exe" ] && [ -x "$dir/src_b/build/bench/$exe" ] || continue
  # Skip executables with no benchmark under the filter (both sides list the same).
  "$dir/src_b/build/bench/$exe" --benchmark_list_tests --benchmark_filter="$filter" 2>/dev/null | grep -q . || continue
  ran+=("$exe")
  for r in $(seq 1 "$rounds"); do
    for side in a b; do
      OMP_NUM_THREADS=1 "$dir/src_$side/build/bench/$exe" --benchmark_filter="$filter" --benchmark_repetitions="$reps" \
        --benchmark_enable_random_interleaving=true --benchmark_min_time=0.2 --benchmark_format=json \
        --benchmark_out="$dir/runs/${exe}_${side}_$r.json" --benchmark_out_format=json >/dev/null 2>&1
    done
  done
done
((${#ran[@]})) || { echo "compare_commits: no benchmark matches '$filter' in both builds" >&2; exit 2; }
echo "== A ${sha[a]:0:10} against B ${sha[b]:0:10}: ${rounds} rounds x ${reps} repetitions, interleaved"
/usr/bin/python3 "$here/scripts/compare_rounds.py" "$gb" "$threshold" "$dir/runs" "$rounds" "${ran[@]}"
