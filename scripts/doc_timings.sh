#!/usr/bin/env bash
# Re-times the wall times the README and docs give (docs/timings.tsv) and prints each
# beside its documented figure. Machines differ, so a figure is judged after scaling
# it by this run's speed: r = measured / documented time of the default suite (its
# midpoint when a range), timed first in the same run. A figure is OK when the
# measured time is within 1.5x of the scaled one (of the nearer end of a scaled
# range; inside the range counts as 1.00), else STALE.
# Usage: scripts/doc_timings.sh [build-dir] [--only NAME...] [--list]
# Exit 0 all OK, 1 some STALE or a command failed, 2 bad arguments or table.
set -euo pipefail
export LC_ALL=C  # EPOCHREALTIME with a '.' decimal point
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
table="${GRAPEBENCH_TIMINGS_TABLE:-$here/docs/timings.tsv}"

usage() { sed -n 8,9p "${BASH_SOURCE[0]}" | sed 's/^# //'; }
bad() { echo "doc_timings: $*" >&2; exit 2; }

build="" list=0 only=()
while [ $# -gt 0 ]; do
  case "$1" in
    --list) list=1 ;;
    --only)
      shift
      while [ $# -gt 0 ] && [[ $1 != --* ]]; do only+=("$1"); shift; done
      [ ${#only[@]} -gt 0 ] || bad "--only needs at least one name"
      continue ;;
    -h|--help) usage; exit 0 ;;
    -*) bad "unknown option $1" ;;
    *) [ -z "$build" ] || bad "one build folder only (got $build and $1)"; build="$1" ;;
  esac
  shift
done
build="$(realpath -m "${build:-${GRAPEBENCH_BUILD_DIR:-$here/build}}")"

# The table: comments (#), a header row, then name, documented, where, command.
[ -r "$table" ] || bad "cannot read $table"
names=()
declare -A doc where cmd
n=0
while IFS= read -r line || [ -n "$line" ]; do
  n=$((n + 1))
  [[ -z $line || $line == \#* || $line == name$'\t'* ]] && continue
  IFS=$'\t' read -r f1 f2 f3 f4 f5 <<<"$line"
  if [ -z "${f4:-}" ] || [ -n "${f5:-}" ]; then bad "$table:$n: want 4 tab-separated columns"; fi
  [[ $f1 =~ ^[A-Za-z0-9_.-]+$ ]] || bad "$table:$n: bad name '$f1'"
  [[ $f2 =~ ^[0-9]+(\.[0-9]+)?(-[0-9]+(\.[0-9]+)?)?$ ]] || bad "$table:$n: '$f2' is not seconds (N or lo-hi)"
  [ -z "${doc[$f1]:-}" ] || bad "$table:$n: '$f1' twice"
  names+=("$f1"); doc[$f1]="$f2"; where[$f1]="$f3"; cmd[$f1]="$f4"
done <"$table"
[ -n "${doc[default]:-}" ] || bad "$table: no 'default' row (the reference)"
for o in "${only[@]}"; do [ -n "${doc[$o]:-}" ] || bad "--only: no entry '$o' in $table"; done

if [ "$list" = 1 ]; then
  for k in "${names[@]}"; do printf '%-28s %-11s %-26s %s\n' "$k" "${doc[$k]}" "${where[$k]}" "${cmd[$k]}"; done
  exit 0
fi

gb="$build/bench/grapebench"
[ -x "$gb" ] || bad "no $gb (build first, or give the build folder)"

# The default suite first, always: every ratio is taken to it.
todo=(default)
for k in "${names[@]}"; do
  [ "$k" = default ] && continue
  if [ ${#only[@]} -gt 0 ]; then [[ " ${only[*]} " == *" $k "* ]] || continue; fi
  todo+=("$k")
done

scratch="$(mktemp -d "${TMPDIR:-/tmp}/doc_timings.XXXXXX")"
trap 'rm -rf "$scratch"' EXIT
results="$scratch/results.tsv"
: >"$results"
read -r load _ </proc/loadavg
started="$(date -u '+%Y-%m-%d %H:%M UTC')"
for k in "${todo[@]}"; do
  out="$scratch/out/$k"
  mkdir -p "$out"
  echo "doc_timings: $k: ${cmd[$k]}" >&2
  t0=$EPOCHREALTIME
  rc=0
  (cd "$here" && GB="$gb" OUT="$out" BUILD="$build" bash -c "${cmd[$k]}") >"$scratch/$k.log" 2>&1 || rc=$?
  t1=$EPOCHREALTIME
  secs="$(/usr/bin/python3 -c "print(f'{$t1 - $t0:.2f}')")"
  echo "doc_timings: $k: $secs s, exit $rc" >&2
  [ "$rc" = 0 ] || tail -n 5 "$scratch/$k.log" | sed 's/^/  | /' >&2
  rm -rf "$out"  # the scenes' outputs run to gigabytes; only the time is kept
  printf '%s\t%s\t%s\t%s\t%s\n' "$k" "${doc[$k]}" "$secs" "$rc" "${where[$k]}" >>"$results"
  if [ "$k" = default ] && [ "$rc" != 0 ]; then echo "doc_timings: the default suite failed: no reference" >&2; exit 1; fi
done

cpu="$(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -n1)"
header="$started, $(nproc) cores ($cpu), load average at start $load, $(basename "$build")"
/usr/bin/python3 - "$results" "$header" <<'EOF'
import sys
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if l.strip()]
def rng(s):
    lo, _, hi = s.partition("-")
    return float(lo), float(hi or lo)
def fmt(x):
    return f"{x:.2f}" if x < 10 else f"{x:.1f}" if x < 100 else f"{x:.0f}"
lo, hi = rng(rows[0][1])
r = float(rows[0][2]) / ((lo + hi) / 2)
print(f"# {sys.argv[2]}")
print(f"# default suite: documented {rows[0][1]} s, measured {rows[0][2]} s, r = {r:.2f}")
print(f"{'name':<28} {'documented':>10} {'measured':>9} {'r':>5} {'scaled':>11} {'meas/scaled':>11}  verdict")
stale = False
for name, doc, meas, rc, where in rows:
    lo, hi = rng(doc)
    slo, shi = lo * r, hi * r
    m = float(meas)
    # The ratio to the nearer end of the scaled range: 1.00 inside it.
    q = m / slo if m < slo else m / shi if m > shi else 1.0
    verdict = f"FAILED (exit {rc})" if rc != "0" else "OK" if 1 / 1.5 <= q <= 1.5 else "STALE"
    stale |= verdict != "OK"
    scaled = fmt(slo) if lo == hi else f"{fmt(slo)}-{fmt(shi)}"
    print(f"{name:<28} {doc:>10} {fmt(m):>9} {r:>5.2f} {scaled:>11} {q:>11.2f}  {verdict}")
sys.exit(1 if stale else 0)
EOF
