#!/usr/bin/python3
"""Mean relative volume error per condition and estimator, with a 95 % t-interval over
the bunches, from a run's results.csv (docs/seed000.md, "Across compactness classes").

    /usr/bin/python3 scripts/condition_errors.py results/runs/seed000_oiv_classes/results.csv PB,VB,CH,visibility_hull
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


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    rows = list(csv.DictReader(open(sys.argv[1], newline="")))
    estimators = sys.argv[2].split(",")
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
