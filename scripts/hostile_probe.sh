#!/bin/bash
# Re-probe of issue 39's hostile inputs against a build (G=path/to/grapebench): each
# line gives the exit code, the seconds and the last line of output. Everything is
# written in a temporary folder, removed at the end.
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
G=$(realpath "${G:-$here/build/bench/grapebench}")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
p() { local name="$1"; shift; local t0=$(date +%s.%N); out=$(timeout -k 5 60 "$@" 2>&1); rc=$?; t=$(echo "$(date +%s.%N) - $t0" | bc); printf '%-34s exit %3s %5.1f s  %s\n' "$name" "$rc" "$t" "$(echo "$out" | grep -v '^\s*$' | tail -1 | cut -c1-150)"; }
body='seed: 5
bunches:
  - preset: table-red
    count: 1
sensor: {type: ideal, width: 80, height: 60}
rig: {type: turntable, views: 2, step_deg: 180, distance: 0.6}
pipeline: {registration: true_poses}
estimators:
  - type: convex_hull
'
printf 'name: latin\n# caf\xe9\n%s' "$body" > latin1.yaml
printf '\xff\xfen\x00a\x00' > utf16.yaml
{ echo "name: bomb"; echo 'a0: &a0 [x,x,x,x,x,x,x,x,x]'; for i in $(seq 1 12); do echo "a$i: &a$i [*a$((i-1)),*a$((i-1)),*a$((i-1)),*a$((i-1)),*a$((i-1)),*a$((i-1)),*a$((i-1)),*a$((i-1)),*a$((i-1))]"; done; echo "unknown_key: *a12"; printf '%s' "$body"; } > bomb.yaml
{ printf 'name: bomb2\nseed: 5\nbunches:\n  - preset: table-red\nestimators:\n  - type: convex_hull\n    x: &a [1,1,1,1,1,1,1,1]\n    y: [*a,*a,*a,*a,*a,*a,*a,*a]\n'; } > bomb_in_estimator.yaml
mkfifo fifo.yaml 2>/dev/null; ln -sf /dev/zero zero.yaml
{ printf 'name: many\nseed: 5\nbunches:\n  - preset: table-red\nestimators:\n'; for i in $(seq 1 10000); do echo "  - {type: convex_hull, name: e$i}"; done; } > many.yaml
printf 'name: "a\\0b"\n%s' "$body" > nul.yaml
printf 'name: sw\n%ssweep:\n  estimators[-1].alpha: [1, 2]\n' "$body" > sweep_neg.yaml
hdr='ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
end_header
0 0 0
0.1 0 0
0 0.1 0
'
printf '%s0 0 0.1\n' "$hdr" > ok.ply
printf '%s1e39 0 0.1\n' "$hdr" > f1e39.ply
printf '%s1e308 0 0.1\n' "$hdr" > p1e308.ply
printf '%s0 0 0.1\n5 5 5\n' "$hdr" > morelines.ply
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0.25 0.5 0.75\n' > binover.ply
printf 'ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float x\nproperty float z\nend_header\n1 2 3\n' > dupprop.ply
cp ok.ply tail.ply; truncate -s 2200M tail.ply
cp ok.ply tail19.ply; printf '\n' >> tail19.ply; truncate -s 1900M tail19.ply
base="$here/results/baseline/default.json"
export base
python3 - <<'PY'
import json
import os
b=open(os.environ['base']).read()
open('dupkey.json','w').write(b.replace('"scene": "default",','"scene": "other", "scene": "default",',1))
j=json.loads(b)
for name,t in [('tol_huge',1e308),('tol_null',None),('tol_neg',-1)]:
    k=dict(j); k['tolerances']=dict(j['tolerances']); k['tolerances']['rmse_rel']=t; json.dump(k,open(name+'.json','w'))
k=dict(j); k['tolerances']=dict(j['tolerances']); k['tolerances']['bogus']=1; json.dump(k,open('tol_unknown.json','w'))
bench={"context":{},"benchmarks":[{"name":"BM_A","run_name":"BM_A","run_type":"iteration","real_time":5,"cpu_time":5,"iterations":1}]}
json.dump(bench,open('notime.json','w'))
bench["benchmarks"][0]["time_unit"]="ms"; json.dump(bench,open('one.json','w'))
e=json.loads(json.dumps(bench)); e["benchmarks"].append(dict(e["benchmarks"][0],error_occurred=True,real_time=1e9)); json.dump(e,open('err.json','w'))
PY
p "scene Latin-1"            $G run latin1.yaml --out out -q
p "scene UTF-16"             $G run utf16.yaml --out out -q
p "alias bomb, unknown key"  $G run bomb.yaml --out out -q
p "alias bomb in estimator"  $G run bomb_in_estimator.yaml --out out -q
p "scene FIFO"               $G run fifo.yaml --out out -q
p "scene -> /dev/zero"       $G run zero.yaml --out out -q
p "10,000 estimators"        $G run many.yaml --out out -q
p "name with NUL"            $G run nul.yaml --out out -q
p "sweep estimators[-1]"     $G run sweep_neg.yaml --out out -q
p "estimate 1e39 cylinder_fit" $G estimate f1e39.ply -e cylinder_fit
p "estimate 1e308 hull"      $G estimate p1e308.ply -e convex_hull
p "PLY more lines"           $G estimate morelines.ply -e convex_hull
p "PLY binary over text"     $G estimate binover.ply -e convex_hull
p "PLY duplicate property"   $G estimate dupprop.ply -e convex_hull
p "PLY 2.2 GB tail"          $G estimate tail.ply -e convex_hull
p "PLY 1.9 GB tail"          $G estimate tail19.ply -e convex_hull
p "cloud FIFO"               $G estimate fifo.yaml -e convex_hull
p "check dup keys"           $G check $base --baseline dupkey.json
p "check tolerance 1e308"    $G check $base --baseline tol_huge.json
p "check tolerance null"     $G check $base --baseline tol_null.json
p "check tolerance -1"       $G check $base --baseline tol_neg.json
p "check tolerance unknown"  $G check $base --baseline tol_unknown.json
p "compare-bench no time_unit" $G compare-bench one.json notime.json
p "compare-bench error_occurred" $G compare-bench one.json err.json
p "compare-bench 1 repetition" $G compare-bench one.json one.json
# A case file that is a FIFO: the run recomputes the case.
printf 'name: fifo_case\n%s' "$body" > fifo_case.yaml
$G run fifo_case.yaml --out out -q >/dev/null 2>&1
f=$(ls out/fifo_case/cases/*.json | head -1); rm -f "$f"; mkfifo "$f"
p "case file FIFO (rerun)"   $G run fifo_case.yaml --out out -q
# Two scenes named alike on one --out.
mkdir -p twin; sed 's/name: fifo_case/name: fifo_case/' fifo_case.yaml > twin/fifo_case.yaml; echo "  - type: pca_box" >> twin/fifo_case.yaml
p "second scene, same name"  $G run twin/fifo_case.yaml --out out -q
