#!/usr/bin/python3
"""How often the pooled berries-found interval of a reduced seed 001 scene holds the
full table's rate (docs/seed001.md, "On Cycles' images"). The reduced scenes take 4
clusters at 8 stations (350, 450, ..., 1050 mm); from a full stereo_pair run
(seed001_black*.yaml: 12 clusters, 38 stations) every choice of 4 of its clusters at
those 8 stations is a subset shaped like them. For each, Wilson's interval over the
berries and the ratio estimator's interval with the pair as the unit
(stereo_rates.py); the share of subsets whose interval holds the rate of all the run's
clusters at the same stations, per light. A 95 % interval should hold it about 95 % of
the time. Every subset is enumerated: nothing is drawn at random.

    /usr/bin/python3 scripts/berry_interval_coverage.py results/runs/seed001_black_ray/results.csv

Options: --clusters N (default 4); --frames I,J,... (the stations' frame indices in the
full run, default 0,5,...,35: 350 to 1050 mm in seed001_black.yaml's 20 mm steps).
"""
import itertools
import sys

import stereo_rates


def main():
    args = sys.argv[1:]
    clusters, frames, files = 4, [str(5 * i) for i in range(8)], []
    i = 0
    while i < len(args):
        if args[i] == "--clusters" and i + 1 < len(args) and args[i + 1].isdigit() and int(args[i + 1]) >= 2:
            clusters = int(args[i + 1])
            i += 2
        elif args[i] == "--frames" and i + 1 < len(args) and all(f.isdigit() for f in args[i + 1].split(",")):
            frames = args[i + 1].split(",")
            i += 2
        elif args[i].startswith("-"):
            sys.exit(__doc__)
        else:
            files.append(args[i])
            i += 1
    if not files:
        sys.exit(__doc__)
    pairs = stereo_rates.read(files, None)
    print("| condition | clusters | rate at the stations, all clusters %% | subsets of %d | Wilson holds it %% | "
          "pairs as the unit holds it %% |" % clusters)
    print("|---|---|---|---|---|---|")
    for cond in sorted(pairs):
        ps = {k: p for k, p in pairs[cond].items() if "cut" in p}
        seeds = sorted({k[0] for k in ps})
        missing = [(s, f) for s in seeds for f in frames if (s, f) not in ps]
        if len(seeds) <= clusters or missing:
            sys.exit("berry_interval_coverage.py: %s: %d clusters (a subset takes %d)%s" % (
                cond, len(seeds), clusters, "; no pair at frame %s of cluster %s" % missing[0][::-1] if missing else ""))
        every = [ps[s, f] for s in seeds for f in frames]
        rate = 100 * sum(p.get("found", 0) for p in every) / max(1, sum(p.get("visible", 0) for p in every))
        n = wilson = ratio = 0
        for chosen in itertools.combinations(seeds, clusters):
            sub = [ps[s, f] for s in chosen for f in frames]
            found = [p.get("found", 0) for p in sub]
            visible = [p.get("visible", 0) for p in sub]
            w, r = stereo_rates.wilson_bounds(sum(found), sum(visible)), stereo_rates.ratio_bounds(found, visible)
            if w is None or r is None:
                continue
            n += 1
            wilson += w[1] <= rate <= w[2]
            ratio += r[1] <= rate <= r[2]
        print("| %s | %d | %.1f | %d | %.1f | %.1f |" % (cond, len(seeds), rate, n, 100 * wilson / max(1, n),
                                                      100 * ratio / max(1, n)))


if __name__ == "__main__":
    main()
