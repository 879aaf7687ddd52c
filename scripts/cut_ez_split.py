#!/usr/bin/python3
"""What carries seed 001's Fig. 11 mean |e_z| (docs/seed001.md): per 100 mm depth bin
(the Fig. 11 columns, all lights), the answered pairs' mean and median |e_z| and the
gross errors (|e_z| above --gross mm) split by where the estimated cutting point lies:

- on the stalk: within --on-stalk mm of the stalk's axis (cut_axis_distance). The
  estimator found the stalk and its depth; the reference, the surface behind the
  detected pixel, is what lies behind the stalk's edge (a leaf a hand's breadth back),
  so e_z is that depth step, not a stereo error;
- off the stalk: a wrong match (NCC's 9 x 9 window on another surface).

Then the mean without the on-stalk pairs, and without any gross one.

    /usr/bin/python3 scripts/cut_ez_split.py results/runs/seed001_black_ray/results.csv

The defaults: 30 mm lies in the gap of the measured |e_z| (none between 17 and 35 mm
on `ray`, summer-black, 363 pairs), 2.5 times the paper's 12 mm; 10 mm is a few stalk
radii (the on-stalk pairs measured 2.7-3.7 mm from the axis).
"""
import argparse
import re
import statistics
import sys

import stereo_rates  # its reader: the pairs of a results.csv


def load(paths, estimator):
    """One dict per answered pair (stereo_rates.read's pairs): station (mm), ez, axis (mm)."""
    out = []
    for pairs in stereo_rates.read(paths, estimator).values():
        for p in pairs.values():
            ez = p.get("ez")
            if ez is None or ez != ez:
                continue  # no cut, or no surface behind the detected pixel
            m = re.search(r"(\d+)mm", p["roi"])
            if not m:
                sys.exit("%s: roi %r names no station (want station_<mm>mm)" % (", ".join(paths), p["roi"]))
            axis = p.get("axis")
            out.append({"station": int(m.group(1)), "ez": ez, "axis": None if axis is None or axis != axis else axis})
    return out


def split(pairs, gross, on_stalk):
    """Rows per 100 mm bin: bin, n, mean, median, on-stalk gross, off-stalk gross, the
    gross pairs' share of the bin's summed |e_z|, mean without on-stalk gross, mean
    without any gross."""
    bins = {}
    for p in pairs:
        bins.setdefault(100 * ((p["station"] + 50) // 100), []).append(p)
    rows = []
    for b in sorted(bins):
        ps = bins[b]
        ae = [abs(p["ez"]) for p in ps]
        big = [p for p in ps if abs(p["ez"]) > gross]
        on = {id(p) for p in big if p.get("axis") is not None and p["axis"] <= on_stalk}
        rest = [abs(p["ez"]) for p in ps if id(p) not in on]
        small = [abs(p["ez"]) for p in ps if abs(p["ez"]) <= gross]
        rows.append((b, len(ps), statistics.fmean(ae), statistics.median(ae), len(on), len(big) - len(on),
                     sum(abs(p["ez"]) for p in big) / sum(ae) if sum(ae) > 0 else 0.0,
                     statistics.fmean(rest) if rest else float("nan"),
                     statistics.fmean(small) if small else float("nan")))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("results", nargs="+", help="results.csv of stereo_pair runs")
    ap.add_argument("--estimator", default="luo_eq6")
    ap.add_argument("--gross", type=float, default=30.0, help="|e_z| above this is gross, mm")
    ap.add_argument("--on-stalk", type=float, default=10.0, help="a cut within this of the stalk's axis is on it, mm")
    a = ap.parse_args()
    pairs = load(a.results, a.estimator)
    if not pairs:
        sys.exit("no answered pair of estimator %r in %s" % (a.estimator, ", ".join(a.results)))
    print("| depth bin, mm | pairs | mean \\|e_z\\| | median | gross on the stalk | gross off it "
          "| gross share of the sum | mean without on-stalk gross | mean without any gross |")
    print("|---|---|---|---|---|---|---|---|---|")
    for b, n, mean, med, on, off, share, wo_on, wo in split(pairs, a.gross, a.on_stalk):
        print("| %d | %d | %.1f | %.1f | %d | %d | %.0f %% | %.1f | %.1f |" % (b, n, mean, med, on, off, 100 * share, wo_on, wo))


if __name__ == "__main__":
    main()
