#!/usr/bin/python3
"""A classification figure (berry AUC by default) over redrawn image noise: per group of
runs, its mean and spread over the draws (`sensor.noise_seed`), and each group's
difference from one of them with a 95 % t-interval from the draws' pooled spread
(docs/seed004.md, "Against Cycles": how finely one row section resolves item 5's 0.02).

    /usr/bin/python3 scripts/auc_draws.py results/runs/seed004_green_sgbm_noise_seed/results.csv \\
        cycles=results/runs/seed004_green_sgbm_cycles/results.csv \\
        cycles=results/runs/seed004_green_sgbm_cycles_noise_seed/results.csv --against cycles

(the first Cycles file from `run scenes/seed004_green_sgbm_cycles.yaml --shard 1/2`,
its 64-sample cell)

A group is a run's scene and condition without the draw key; LABEL=FILE puts every row
of FILE in group LABEL (with the condition, if FILE has more than one), so draws made by
two scene files (a redraw written as its own scene) count as one group. A draw is a file
and its draw key's value. The pooled spread assumes the draws scatter alike in every
group with two or more of them; each group's own is printed beside it. A draw whose
figure is undefined (nan: the estimator scored no berry point, or only berries) is left
out of the means and counted beside them.
"""
import argparse
import collections
import csv
import math
import os
import statistics
import sys

from condition_errors import T975  # Student's t, 95 %


def fail(message):
    print("auc_draws.py: " + message, file=sys.stderr)
    sys.exit(2)


def read(specs, draw_key, quantity, estimators):
    """{group: {estimator: {draw: value}}} in the order met."""
    groups = collections.OrderedDict()
    for spec in specs:
        # LABEL=FILE, or a FILE (whose name may hold a "=")
        label, _, path = ("", "", spec) if os.path.exists(spec) or "=" not in spec else spec.partition("=")
        try:
            with open(path, newline="") as fh:
                rows = [r for r in csv.DictReader(fh) if r.get("quantity") == quantity]
        except OSError as e:
            fail("%s: %s" % (path, e.strerror))
        if not rows:
            fail("%s: no rows of quantity %s" % (path, quantity))
        for column in ("scene", "condition", "estimator", "estimate"):
            if column not in rows[0]:
                fail("%s: no column %s (a grapebench results.csv?)" % (path, column))
        short = draw_key.rsplit(".", 1)[-1] + "="

        def condition(r):
            return " ".join(t for t in r["condition"].split() if not t.startswith(short))

        conditions = list(dict.fromkeys(condition(r) for r in rows))
        for r in rows:
            if estimators and r["estimator"] not in estimators:
                continue
            c = condition(r)
            if label:
                g = label if len(conditions) == 1 else "%s: %s" % (label, c)
            else:
                g = "%s: %s" % (r["scene"], c)
            try:
                v = float(r["estimate"])
            except ValueError:
                fail("%s: estimate %r of %s is not a number" % (path, r["estimate"], r["estimator"]))
            draw = (path, r.get(draw_key, "0"))
            cell = groups.setdefault(g, collections.OrderedDict()).setdefault(r["estimator"], {})
            if draw in cell:
                fail("%s: two rows of %s for %s at %s=%s (more than one bunch? one bunch a draw is read)"
                     % (path, r["estimator"], g, draw_key, draw[1]))
            cell[draw] = v
    if not groups:
        fail("no rows of the estimators %s" % ", ".join(estimators))
    return groups


def defined(cells, estimator):
    """The estimator's figures over the draws, the undefined (nan) ones left out."""
    return [v for v in cells.get(estimator, {}).values() if not math.isnan(v)]


def undefined(cells, estimator):
    return sum(1 for v in cells.get(estimator, {}).values() if math.isnan(v))


def pooled(groups, estimator):
    """The draws' pooled standard deviation and its degrees of freedom, or None."""
    ss, df = 0.0, 0
    for cells in groups.values():
        v = defined(cells, estimator)
        if len(v) >= 2:
            ss += statistics.variance(v) * (len(v) - 1)
            df += len(v) - 1
    return (math.sqrt(ss / df), df) if df else None


def difference(a, b, spread):
    """Mean of a minus mean of b and the 95 % interval's half width (None without a spread)."""
    d = statistics.mean(a) - statistics.mean(b)
    if spread is None:
        return d, None
    s, df = spread
    t = T975[min(df, len(T975)) - 1]
    return d, t * s * math.sqrt(1 / len(a) + 1 / len(b))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+", metavar="[LABEL=]RESULTS.csv")
    ap.add_argument("--draw-key", default="sensor.noise_seed", help="the column that numbers the draws")
    ap.add_argument("--quantity", default="auc_berry")
    ap.add_argument("--estimators", default="", help="comma separated (default: every one)")
    ap.add_argument("--against", default="", help="the group every other is compared with")
    ap.add_argument("--target", type=float, default=0.02, help="the agreement asked for (item 5: 0.02)")
    a = ap.parse_args()
    estimators = [e for e in a.estimators.split(",") if e]
    groups = read(a.files, a.draw_key, a.quantity, estimators)
    if not estimators:
        estimators = list(dict.fromkeys(e for cells in groups.values() for e in cells))
    if a.against and a.against not in groups:
        fail("--against %r is not a group; the groups: %s" % (a.against, "; ".join(groups)))

    print("| %s over draws: mean (sd) | draws | %s |" % (a.quantity, " | ".join(estimators)))
    print("|---|---|" + "---|" * len(estimators))
    spreads = {e: pooled(groups, e) for e in estimators}
    for g, cells in groups.items():
        n = max(len(cells.get(e, {})) for e in estimators)
        out = []
        for e in estimators:
            v = defined(cells, e)
            text = "-" if not v else "%.3f (%.3f)" % (statistics.mean(v), statistics.stdev(v)) if len(v) > 1 \
                else "%.3f" % v[0]
            nan = undefined(cells, e)
            out.append(text + (", %d undefined" % nan if nan else ""))
        print("| %s | %d | %s |" % (g, n, " | ".join(out)))
    print("| pooled sd (degrees of freedom) | | %s |"
          % " | ".join("%.4f (%d)" % spreads[e] if spreads[e] else "-" for e in estimators))
    if not a.against:
        return
    print()
    print("| minus %s, mean of the draws [95 %%]; * within %g, ** the interval too | %s |"
          % (a.against, a.target, " | ".join(estimators)))
    print("|---|" + "---|" * len(estimators))
    for g, cells in groups.items():
        if g == a.against:
            continue
        out = []
        for e in estimators:
            x, y = defined(cells, e), defined(groups[a.against], e)
            if not x or not y:
                out.append("-")
                continue
            d, h = difference(x, y, spreads[e])
            mark = "**" if h is not None and abs(d) + h <= a.target else "*" if abs(d) <= a.target else ""
            out.append(("%+.3f" % d if h is None else "%+.3f [%+.3f, %+.3f]" % (d, d - h, d + h)) + mark)
        print("| %s | %s |" % (g, " | ".join(out)))


if __name__ == "__main__":
    main()
