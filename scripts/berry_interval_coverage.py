#!/usr/bin/python3
"""How often the pooled berries-found interval of a reduced seed 001 scene holds the
full table's rate (docs/seed001.md, "On Cycles' images"). The reduced scenes take 4
clusters at 8 stations (350, 450, ..., 1050 mm); from a full stereo_pair run
(seed001_black*.yaml: 12 clusters, 38 stations) every choice of 4 of its clusters at
those 8 stations is a subset shaped like them. For each, three intervals of the pooled
rate (stereo_rates.py): Wilson's over the berries, the ratio estimator's with the pair
as the unit, and with the cluster as the unit; each narrowed by the finite-population
factor sqrt(1 - 4 / 12), since the rate they are checked against is that of the run's
own 12 clusters at the same stations (without it every interval would look about a
fifth too good). Printed: the share of subsets whose interval holds that rate, and the
interval's mean width. A 95 % interval should hold it about 95 % of the time. Every
subset is enumerated: nothing is drawn at random.

    /usr/bin/python3 scripts/berry_interval_coverage.py results/runs/seed001_black_ray/results.csv

Options: --estimator NAME (default luo_eq6); --clusters N (default 4); --frames I,J,...
(the stations' frame indices in the full run, default 0,5,...,35: 350 to 1050 mm in
seed001_black.yaml's 20 mm steps).
"""
import argparse
import collections
import itertools
import math
import sys

import stereo_rates


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="+", help="stereo_pair runs' results.csv")
    ap.add_argument("--estimator", default="luo_eq6")
    ap.add_argument("--clusters", type=int, default=4)
    ap.add_argument("--frames", default=",".join(str(5 * i) for i in range(8)))
    a = ap.parse_args()
    frames = a.frames.split(",")
    if a.clusters < 2 or not all(f.isdigit() for f in frames):
        ap.error("--clusters takes an integer >= 2 and --frames comma-separated frame indices")
    files, estimator, clusters = a.files, a.estimator, a.clusters
    pairs = stereo_rates.read(files, estimator)
    kinds = ("Wilson", "pairs as the unit", "clusters as the unit")
    print("| %s: condition | clusters | rate at the stations, all clusters %% | subsets of %d | %s |" % (
        estimator, clusters, " | ".join("%s: holds it %%, mean width (points)" % k for k in kinds)))
    print("|---|---|---|---|" + "---|" * len(kinds))
    for cond in sorted(pairs):
        ps = {k: p for k, p in pairs[cond].items() if "cut" in p}
        seeds = sorted({k[0] for k in ps})
        missing = [(s, f) for s in seeds for f in frames if (s, f) not in ps]
        if len(seeds) <= clusters or missing:
            sys.exit("berry_interval_coverage.py: %s: %d clusters (a subset takes %d)%s" % (
                cond, len(seeds), clusters, "; no pair at frame %s of cluster %s" % missing[0][::-1] if missing else ""))
        every = [ps[s, f] for s in seeds for f in frames]
        rate = 100 * sum(p.get("found", 0) for p in every) / max(1, sum(p.get("visible", 0) for p in every))
        fpc = math.sqrt(1 - clusters / len(seeds))
        n = collections.Counter()
        held, width = collections.Counter(), collections.Counter()
        for chosen in itertools.combinations(seeds, clusters):
            found = [[ps[s, f].get("found", 0) for f in frames] for s in chosen]
            visible = [[ps[s, f].get("visible", 0) for f in frames] for s in chosen]
            bounds = {
                kinds[0]: stereo_rates.wilson_bounds(sum(map(sum, found)), sum(map(sum, visible))),
                kinds[1]: stereo_rates.ratio_bounds(sum(found, []), sum(visible, [])),
                kinds[2]: stereo_rates.ratio_bounds(list(map(sum, found)), list(map(sum, visible))),
            }
            for k, b in bounds.items():
                if b is None:
                    continue
                r, lo, hi = b
                lo, hi = r - fpc * (r - lo), r + fpc * (hi - r)
                n[k] += 1
                held[k] += lo <= rate <= hi
                width[k] += hi - lo
        cells = ["%.1f, %.1f" % (100 * held[k] / n[k], width[k] / n[k]) if n[k] else "-" for k in kinds]
        print("| %s | %d | %.1f | %d | %s |" % (cond, len(seeds), rate, max(n.values(), default=0), " | ".join(cells)))


if __name__ == "__main__":
    main()
