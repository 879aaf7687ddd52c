#!/usr/bin/env bash
# Runs a scene on a Slurm cluster: an array job of shards, then a merge job.
#
# Usage: scripts/slurm_sweep.sh SCENE --shards N --out DIR [--threads T] [--tasks LIST]
#                               [-- SBATCH_OPTION...]
#
# The array (sbatch --array=LIST, default 0-(N-1)), one task per shard i:
#     $GRAPEBENCH run SCENE --shard i/N --threads T --out DIR/shards/i
# with --cpus-per-task=T (T defaults to 1). Then, with --dependency=afterany on the
# array (it runs even when a task failed or was cancelled):
#     $GRAPEBENCH merge SCENE --from DIR/shards/0/<scene name> ... --out DIR/merged
# The merge writes the same results.csv, summary.json and report as an unsharded
# run. When a task did not finish it exits 2 (the job FAILED) and its log names the
# missing shards ("missing shards: 1/4 2/4"); resubmit only those with --tasks 1,2,
# which submits the merge again too. Every finished case is reused: resubmitting a
# finished array computes nothing (each task's log says "0 computed").
#
# Prints "array job: ID" and "merge job: ID". Logs: DIR/logs/<array id>_<task>.out,
# DIR/logs/merge_<job id>.out. Options after `--` go to both sbatch calls
# (--partition, --time, --account, --hold...). GRAPEBENCH is the binary (default:
# build/bench/grapebench of this checkout); it, SCENE and DIR must be on a file
# system every node sees. Paths are made absolute before submission.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

usage() {
  sed -n '4,5p' "${BASH_SOURCE[0]}" | sed 's/^# //' >&2
  exit 2
}
die() {
  echo "slurm_sweep: $*" >&2
  exit 2
}

scene="" shards="" out="" threads=1 tasks=""
sbatch_extra=()
while (($#)); do
  case "$1" in
    --shards) shards="${2:-}"; shift 2 || usage ;;
    --out) out="${2:-}"; shift 2 || usage ;;
    --threads) threads="${2:-}"; shift 2 || usage ;;
    --tasks) tasks="${2:-}"; shift 2 || usage ;;
    --) shift; sbatch_extra=("$@"); break ;;
    -h | --help) usage ;;
    -*) die "unknown option $1" ;;
    *) [ -z "$scene" ] || die "one scene only (got $scene and $1)"; scene="$1"; shift ;;
  esac
done
if [ -z "$scene" ] || [ -z "$shards" ] || [ -z "$out" ]; then usage; fi
[ -f "$scene" ] || die "$scene: no such scene file"
[[ "$shards" =~ ^[1-9][0-9]*$ ]] || die "--shards expects a positive count, got '$shards'"
[[ "$threads" =~ ^[1-9][0-9]*$ ]] || die "--threads expects a positive count, got '$threads'"
# Indices and ranges as sbatch --array takes them ("2", "1,3", "0-7"), each below N.
if [ -z "$tasks" ]; then
  tasks="0-$((shards - 1))"
else
  [[ "$tasks" =~ ^[0-9]+(-[0-9]+)?(,[0-9]+(-[0-9]+)?)*$ ]] || die "--tasks expects indices like 2 or 1,3 or 0-3, got '$tasks'"
  for i in $(tr ',-' '  ' <<<"$tasks"); do
    ((10#$i < shards)) || die "--tasks: $i is not a shard of $shards (0-$((shards - 1)))"
  done
fi
command -v sbatch >/dev/null || die "sbatch not found: run this on a Slurm submit host"

gb="${GRAPEBENCH:-$here/build/bench/grapebench}"
gb="$(realpath "$gb")"
[ -x "$gb" ] || die "$gb: not an executable (set GRAPEBENCH to the grapebench binary)"
scene="$(realpath "$scene")"
mkdir -p "$out/shards" "$out/logs"
out="$(realpath "$out")"

# The scene's folder inside each shard's --out: its `name:`, else the file's stem
# (bench/scene_file.cpp); names are plain (A-Z a-z 0-9 _ - .), quotes aside.
name="$(sed -n -E "s/^name:[[:space:]]*[\"']?([A-Za-z0-9_.-]+)[\"']?[[:space:]]*(#.*)?\$/\\1/p" "$scene" | head -n 1)"
[ -n "$name" ] || name="$(basename "${scene%.*}")"

q() { printf '%q' "$1"; }
array_id="$(sbatch --parsable --job-name "grapebench-$name" --array "$tasks" --cpus-per-task "$threads" \
  --output "$out/logs/%A_%a.out" "${sbatch_extra[@]}" <<EOF
#!/bin/bash
exec $(q "$gb") run $(q "$scene") --shard "\$SLURM_ARRAY_TASK_ID/$shards" --threads $threads \\
    --out $(q "$out/shards")/"\$SLURM_ARRAY_TASK_ID"
EOF
)"
array_id="${array_id%%;*}"  # "id;cluster" on a multi-cluster setup
echo "array job: $array_id (tasks $tasks of $shards)"

from=""
for ((i = 0; i < shards; i++)); do from+=" --from $(q "$out/shards/$i/$name")"; done
merge_id="$(sbatch --parsable --job-name "grapebench-$name-merge" --dependency "afterany:$array_id" \
  --cpus-per-task 1 --output "$out/logs/merge_%j.out" "${sbatch_extra[@]}" <<EOF
#!/bin/bash
exec $(q "$gb") merge $(q "$scene")$from --out $(q "$out/merged")
EOF
)"
merge_id="${merge_id%%;*}"
echo "merge job: $merge_id (after array job $array_id ends; results in $out/merged)"
