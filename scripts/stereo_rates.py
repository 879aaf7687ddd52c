#!/usr/bin/python3
"""Seed 001's rates per condition from stereo_pair runs' results.csv (docs/seed001.md,
"On Cycles' images"): cut success and berries found with Wilson 95 % intervals (for the
berries also with the pair and with the cluster as the unit), the
pairs reaching the berry stage, the cluster region's median IoU; and, with --pair A B,
the two conditions compared pair for pair (the same bunch seed and station), berries
found B minus A in points with a t-interval over the pairs (the pair is the unit: its
berries are not independent draws, so the pooled Wilson interval is too narrow).

    /usr/bin/python3 scripts/stereo_rates.py results/runs/seed001_cycles/results.csv \\
        --pair "seed001_cycles: light=overcast renderer=ray" "seed001_cycles: light=overcast renderer=cycles"

Conditions are named "<scene>: <condition>"; several files may be given, and --pair
may compare conditions of different runs when their bunch seeds and stations match.
"""
import collections
import csv
import math
import statistics
import sys

from condition_errors import T975, interval  # Student's t, 95 %


def wilson_bounds(k, n, z=1.96):
    """Rate k / n and Wilson's 95 % interval, in %; None when n is 0."""
    if n == 0:
        return None
    p = k / n
    d = 1 + z * z / n
    c = p + z * z / (2 * n)
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return 100 * p, 100 * (c - h) / d, 100 * (c + h) / d


def wilson(k, n, z=1.96):
    b = wilson_bounds(k, n, z)
    return "%.1f (%.1f-%.1f)" % b if b else "-"


def ratio_bounds(found, visible):
    """The pooled rate sum(found) / sum(visible) with each list entry as a unit (a pair,
    or a cluster's pairs summed), in %: the ratio estimator's linearised variance,
    n / (n - 1) sum (f_i - R v_i)^2 / (sum v)^2, and Student's t over the n units
    (Cochran, Sampling Techniques, 1977, Sec. 6.4; no finite-population factor). A pair's
    berries are not independent draws (a pair whose cut is not matched scores none of
    them), so Wilson's interval over the berries is too narrow. How often each holds
    the full tables' rate is measured by berry_interval_coverage.py (docs/seed001.md).
    None with fewer than 2 units, no visible berry, or every unit at the same rate (a
    variance estimate of 0 is no interval)."""
    n, v = len(found), sum(visible)
    if n < 2 or v == 0:
        return None
    r = sum(found) / v
    ss = sum((f - r * w) ** 2 for f, w in zip(found, visible))
    if ss <= 1e-12 * v * v:
        return None
    se = math.sqrt(n / (n - 1) * ss) / v
    h = T975[min(n - 1, len(T975)) - 1] * se
    return 100 * r, 100 * max(0.0, r - h), 100 * min(1.0, r + h)


def ratio_interval(found, visible):
    b = ratio_bounds(found, visible)
    return "%.1f (%.1f-%.1f)" % b if b else "-"


def t_interval(values):
    return interval(values) if values else "-"


def failure(message):
    """Why a cut failed; no message: it was found and matched but lies off the stalk."""
    if not message:
        return "off the stalk"
    for prefix, name in (("cutting point not matched", "not matched"), ("the peduncle ROI is empty", "ROI empty"),
                         ("no line in the peduncle ROI", "no line")):
        if message.startswith(prefix):
            return name
    return "other"


def read(files, estimator):
    """Per condition, per pair (seed, frame): cut ok, the cut's message, berries found and visible, IoU,
    e_z with the pair's roi and the cut's distance to the stalk's axis."""
    pairs = collections.defaultdict(dict)
    for f in files:
        with open(f, newline="") as fh:
            for r in csv.DictReader(fh):
                if estimator and r["estimator"] != estimator:
                    continue
                cond = "%s: %s" % (r["scene"], r["condition"])
                p = pairs[cond].setdefault((r["seed"], r["frame"]), {})
                q = r["quantity"]
                if q == "cut_success":
                    p["cut"] = float(r["estimate"]) == 1
                    p["message"] = r["message"]
                    # Rows without a message reached every stage (the berries' too).
                    p["ran"] = not r["message"]
                elif q == "berries_found" and r["ok"] == "1":
                    p["found"], p["visible"] = float(r["estimate"]), float(r["truth"])
                elif q == "cluster_iou" and r["ok"] == "1":
                    p["iou"] = float(r["estimate"])
                elif q == "cut_z":  # e_z (scripts/cut_ez_split.py); NaN without a cut
                    p["ez"], p["roi"] = float(r["error"] or "nan"), r["roi"]
                elif q == "cut_axis_distance":
                    p["axis"] = float(r["estimate"] or "nan")
    if not pairs:
        sys.exit("stereo_rates.py: no stereo_pair rows in %s" % ", ".join(files))
    return pairs


def table(pairs):
    print("| condition | pairs | cut success % | not matched / ROI empty / no line / off the stalk or other | "
          "berries found / visible %, all pairs | the same, pairs as the unit | clusters as the unit | pairs reaching the berry stage | berries on them % | cluster IoU, median |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for cond in sorted(pairs):
        cut = {k: p for k, p in pairs[cond].items() if "cut" in p}
        ps = list(cut.values())
        n, ok = len(ps), sum(p["cut"] for p in ps)
        split = collections.Counter(failure(p["message"]) for p in ps if not p["cut"])
        found = sum(p.get("found", 0) for p in ps)
        visible = sum(p.get("visible", 0) for p in ps)
        ran = [p for p in ps if p["ran"]]
        rf, rv = sum(p.get("found", 0) for p in ran), sum(p.get("visible", 0) for p in ran)
        ious = [p["iou"] for p in ps if "iou" in p]
        per_cluster = collections.defaultdict(lambda: [0.0, 0.0])
        for (seed, _), p in cut.items():
            per_cluster[seed][0] += p.get("found", 0)
            per_cluster[seed][1] += p.get("visible", 0)
        print("| %s | %d | %s [%d] | %d / %d / %d / %d | %s | %s | %s | %d | %s | %s |" % (
            cond, n, wilson(ok, n), ok, split["not matched"], split["ROI empty"], split["no line"],
            split["off the stalk"] + split["other"], wilson(found, visible),
            ratio_interval([p.get("found", 0) for p in ps], [p.get("visible", 0) for p in ps]),
            ratio_interval([c[0] for c in per_cluster.values()], [c[1] for c in per_cluster.values()]),
            len(ran), wilson(rf, rv),
            "%.2f" % statistics.median(ious) if ious else "-"))


def compare(pairs, a, b):
    for c in (a, b):
        if c not in pairs:
            sys.exit("stereo_rates.py: no condition '%s'; the conditions are: %s" % (c, "; ".join(sorted(pairs))))
    common = sorted(set(pairs[a]) & set(pairs[b]))
    both = collections.Counter()
    diffs, diffs_ran = [], []
    for k in common:
        pa, pb = pairs[a][k], pairs[b][k]
        if "cut" not in pa or "cut" not in pb:
            continue
        both[pa["cut"], pb["cut"]] += 1
        if pa.get("visible") and pb.get("visible"):
            d = 100 * (pb["found"] / pb["visible"] - pa["found"] / pa["visible"])
            diffs.append(d)
            if pa["ran"] and pb["ran"]:
                diffs_ran.append(d)
    print("\n%s minus %s, pair for pair (%d pairs):" % (b, a, len(common)))
    print("- cut success: both %d, only the first %d, only the second %d, neither %d" % (
        both[True, True], both[True, False], both[False, True], both[False, False]))
    print("- berries found, points: all pairs %s (%d); pairs where both reach the berry stage %s (%d)" % (
        t_interval(diffs), len(diffs), t_interval(diffs_ran), len(diffs_ran)))


def main():
    args = sys.argv[1:]
    estimator, compares = None, []
    files = []
    i = 0
    while i < len(args):
        if args[i] == "--estimator" and i + 1 < len(args):
            estimator = args[i + 1]
            i += 2
        elif args[i] == "--pair" and i + 2 < len(args):
            compares.append((args[i + 1], args[i + 2]))
            i += 3
        elif args[i].startswith("-"):
            sys.exit(__doc__)
        else:
            files.append(args[i])
            i += 1
    if not files:
        sys.exit(__doc__)
    pairs = read(files, estimator)
    table(pairs)
    for a, b in compares:
        compare(pairs, a, b)


if __name__ == "__main__":
    main()
