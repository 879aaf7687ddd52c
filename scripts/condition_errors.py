#!/usr/bin/python3
"""Mean relative volume error per condition and estimator, with a 95 % t-interval over
the bunches, from a run's results.csv (docs/seed000.md, "Across compactness classes").

    /usr/bin/python3 scripts/condition_errors.py results/runs/seed000_oiv_classes/results.csv PB,VB,CH,visibility_hull

With --paired KEY (a sweep column taking two values, for example
bunches.bend_probability), the difference second value minus first, bunch for bunch,
in points of relative error, per the remaining conditions and estimator (on an axis that
changes the bunches themselves, a preset, the pairs are unrelated bunches: the interval
holds, without a pairing's gain):

    /usr/bin/python3 scripts/condition_errors.py results/runs/seed000_bent/results.csv PB,VB,CH,visibility_hull --paired bunches.bend_probability
"""
import collections
import csv
import math
import statistics
import sys

# Two-sided 97.5 % quantiles of Student's t for 1..30 degrees of freedom.
T975 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145,
        2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048,
        2.045, 2.042]


def interval(values):
    m = statistics.mean(values)
    if len(values) < 2:
        return "%+.1f" % m
    t = T975[min(len(values) - 1, len(T975)) - 1]
    h = t * statistics.stdev(values) / math.sqrt(len(values))
    return "%+.1f [%+.1f, %+.1f]" % (m, m - h, m + h)


def paired(rows, estimators, key):
    if not rows or key not in rows[0]:
        sys.exit("condition_errors.py: %s is not a column of the results" % key)
    values = list(dict.fromkeys(r[key] for r in rows))  # the sweep's order
    try:
        values.sort(key=float)
    except ValueError:  # a string axis (a registration type, a preset) keeps the sweep's order
        pass
    if len(values) != 2:
        sys.exit("condition_errors.py: %s takes %d values (%s); --paired needs 2" % (key, len(values), ", ".join(values)))
    sweep = [c for c in rows[0] if "." in c and c != key]  # the other sweep columns
    errors = collections.defaultdict(dict)
    for r in rows:
        if r["quantity"] == "volume" and r["estimator"] in estimators and r["ok"] == "1":
            rest = " ".join("%s=%s" % (c, r[c]) for c in sweep)
            errors[rest, r["estimator"], r["bunch"]][r[key]] = float(r["rel_error_pct"])
    diffs = collections.defaultdict(list)
    for (rest, e, _), d in errors.items():
        if len(d) == 2:
            diffs[rest, e].append(d[values[1]] - d[values[0]])
    print("| condition | " + " | ".join("%s, %s=%s minus %s, points" % (e, key, values[1], values[0]) for e in estimators) + " |")
    print("|---|" + "---|" * len(estimators))
    for rest in sorted({k[0] for k in diffs}):
        cells = [interval(diffs[rest, e]) + " (%d)" % len(diffs[rest, e]) if diffs[rest, e] else "" for e in estimators]
        print("| %s | %s |" % (rest or "all", " | ".join(cells)))


def main():
    args = sys.argv[1:]
    key = None
    if "--paired" in args:
        i = args.index("--paired")
        if i + 1 >= len(args):
            sys.exit(__doc__)
        key = args[i + 1]
        del args[i:i + 2]
    if len(args) != 2:
        sys.exit(__doc__)
    rows = list(csv.DictReader(open(args[0], newline="")))
    estimators = args[1].split(",")
    if key:
        paired(rows, estimators, key)
        return
    errors = collections.defaultdict(list)
    rotation = collections.defaultdict(list)
    for r in rows:
        if r["quantity"] != "volume" or r["estimator"] not in estimators:
            continue
        if r["ok"] == "1":
            errors[r["condition"], r["estimator"]].append(float(r["rel_error_pct"]))
        if r["estimator"] == estimators[0]:
            rotation[r["condition"]].append(float(r["rotation_error_max_deg"] or 0))
    print("| condition | " + " | ".join(e + ", %" for e in estimators) + " | largest view rotation error, mean, deg |")
    print("|---|" + "---|" * (len(estimators) + 1))
    for c in sorted(rotation):
        cells = [interval(errors[c, e]) if errors[c, e] else "" for e in estimators]
        print("| %s | %s | %.0f |" % (c, " | ".join(cells), statistics.mean(rotation[c])))


if __name__ == "__main__":
    main()
