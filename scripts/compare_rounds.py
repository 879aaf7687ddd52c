#!/usr/bin/python3
"""The table of scripts/compare_commits.sh.

Usage: compare_rounds.py GRAPEBENCH THRESHOLD RUNS_DIR ROUNDS EXE...
RUNS_DIR holds <exe>_<a|b>_<round>.json (Google Benchmark JSON with repetitions).
Per exe the rounds of each side are joined into <exe>_<side>.json and handed to
`grapebench compare-bench` (ratio of medians over every repetition, U test); then,
per benchmark, the ratio of medians of each round: "B faster" or "B slower" only
when every round is beyond 1 -/+ THRESHOLD, otherwise "~" (the spread verdict).
Exit: compare-bench's worst exit code (1: a slowdown flagged).
"""
import json
import os
import re
import statistics
import subprocess
import sys


def load(path):
    with open(path, encoding="utf-8") as f:
        # Google Benchmark writes bare NaN / Infinity for undefined aggregates.
        text = re.sub(r'(?<!")\b(-?Infinity|NaN)\b(?!")', "null", f.read())
    return json.loads(text)


def times(doc):
    """run_name -> repetition times (ns), iteration rows only."""
    unit = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}
    out = {}
    for b in doc.get("benchmarks", []):
        if b.get("run_type", "iteration") != "iteration" or b.get("error_occurred"):
            continue
        out.setdefault(b.get("run_name", b["name"]), []).append(b["real_time"] * unit[b.get("time_unit", "ns")])
    return out


def main(argv):
    if len(argv) < 6:
        print(__doc__, file=sys.stderr)
        return 2
    gb, threshold, runs, rounds, exes = argv[1], argv[2], argv[3], int(argv[4]), argv[5:]
    worst = 0
    rows = []
    for exe in exes:
        joined = {}
        per_round = {"a": [], "b": []}
        for side in "ab":
            docs = [load(os.path.join(runs, f"{exe}_{side}_{r}.json")) for r in range(1, rounds + 1)]
            per_round[side] = [times(d) for d in docs]
            merged = dict(docs[0])
            merged["benchmarks"] = [b for d in docs for b in d.get("benchmarks", [])
                                    if b.get("run_type", "iteration") == "iteration"]
            joined[side] = os.path.join(runs, f"{exe}_{side}.json")
            with open(joined[side], "w", encoding="utf-8") as f:
                json.dump(merged, f)
        print(f"-- {exe}: grapebench compare-bench (A = baseline, B = contender), threshold {threshold}")
        p = subprocess.run([gb, "compare-bench", joined["a"], joined["b"], "--threshold", threshold],
                           capture_output=True, text=True)
        print(p.stdout, end="")
        if p.returncode not in (0, 1):
            print(p.stderr, end="", file=sys.stderr)
            return 2
        worst = max(worst, p.returncode)
        for name in per_round["a"][0]:
            ratios = []
            for ra, rb in zip(per_round["a"], per_round["b"]):
                if name in ra and name in rb:
                    ratios.append(statistics.median(rb[name]) / statistics.median(ra[name]))
            all_a = [t for r in per_round["a"] for t in r.get(name, [])]
            all_b = [t for r in per_round["b"] for t in r.get(name, [])]
            if not ratios or not all_a or not all_b:
                continue
            lo, hi = min(ratios), max(ratios)
            t = float(threshold)
            if hi < 1 - t:
                verdict = "B faster"
            elif lo > 1 + t:
                verdict = "B slower"
            elif hi < 1 or lo > 1:
                verdict = f"~ (every round {'under' if hi < 1 else 'over'} 1, within {t:.0%})"
            else:
                verdict = "~ (rounds disagree)"
            rows.append((name, statistics.median(all_a) / 1e6, statistics.median(all_b) / 1e6,
                         statistics.median(all_b) / statistics.median(all_a), lo, hi, verdict))
    print(f"\n{'benchmark':<44} {'A median':>11} {'B median':>11} {'B/A':>7} {'rounds B/A':>15}  verdict")
    for name, ma, mb, r, lo, hi, v in rows:
        print(f"{name:<44} {ma:8.4g} ms {mb:8.4g} ms {r:7.3f} {lo:7.3f}-{hi:<7.3f}  {v}")
    return worst


if __name__ == "__main__":
    sys.exit(main(sys.argv))
