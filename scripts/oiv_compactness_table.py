#!/usr/bin/python3
"""Validation table of the OIV 204 compactness classes (docs/synth.md).

Runs `grapebench synth --no-mesh` for each preset and class (and the continuous
`compactness` settings for comparison), then prints one Markdown row per setting:
berries, solid volume, solid / convex hull, solid / alpha wrap (a tight envelope: CGAL's
alpha wrap with a carving ball of --alpha metres, about a berry's radius; 0 leaves the
column out), berries in contact, contact depth and the berries the packing dropped, each
as the mean over the bunches (sd in brackets).

    /usr/bin/python3 scripts/oiv_compactness_table.py build/bench/grapebench \
        --count 16 --seed 424242 --out results/oiv_table
"""
import argparse
import csv
import os
import statistics
import subprocess
import sys


def run(grapebench, preset, sets, count, seed, out, alpha):
    os.makedirs(out, exist_ok=True)
    cmd = [grapebench, "synth", "--preset", preset, "--count", str(count), "--seed", str(seed),
           "--no-mesh", "--out", out]
    if alpha > 0:
        cmd += ["--alpha-wrap", str(alpha)]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.csv"), newline="") as f:
        return list(csv.DictReader(f))


def cell(rows, key, fmt, scale=1.0):
    values = [float(r[key]) * scale for r in rows]
    sd = statistics.stdev(values) if len(values) > 1 else 0.0
    return (fmt + " (" + fmt + ")") % (statistics.mean(values), sd)


def parser(doc, out):
    """The arguments every table script of the generator takes."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("grapebench")
    ap.add_argument("--count", type=int, default=16)
    ap.add_argument("--seed", type=int, default=424242)
    ap.add_argument("--out", default=out)
    ap.add_argument("--alpha", type=float, default=0.01, help="alpha wrap's carving radius, m; 0: no wrap")
    return ap


def main():
    ap = parser(__doc__, "results/oiv_table")
    ap.add_argument("--presets", default="table-red,wine-red,summer-black,green-table")
    ap.add_argument("--classes", default="1,3,5,7,9")
    ap.add_argument("--settings", default="all", choices=["all", "classes"],
                    help="classes: the OIV classes and the densest continuous setting only")
    a = ap.parse_args()
    wrap = a.alpha > 0
    print("| preset | setting | berries | solid cm3 | solid / hull | %sberries in contact | "
          "contact depth, mean | contact depth, max | dropped by packing |" % ("solid / wrap | " if wrap else ""))
    print("|---|---|---|---|---|---|---|---|---|" + ("---|" if wrap else ""))
    for preset in a.presets.split(","):
        settings = []
        if a.settings == "all":
            settings += [("preset's own", [])]
            settings += [("compactness 0", ["compactness=0", "oiv_compactness=0"])]
        # A variety preset's own class would override the continuous settings.
        settings += [("compactness 1", ["compactness=1", "oiv_compactness=0"])]
        if a.settings == "all":
            settings += [("compactness 1, press 0.3", ["compactness=1", "max_press_depth=0.3", "oiv_compactness=0"])]
        settings += [("OIV %s" % k, ["oiv_compactness=%s" % k]) for k in a.classes.split(",")]
        for name, sets in settings:
            out = os.path.join(a.out, preset, name.replace(" ", "_").replace(",", ""))
            rows = run(a.grapebench, preset, sets, a.count, a.seed, out, a.alpha)
            for r in rows:
                if wrap:
                    r["solid_over_wrap"] = float(r["solid_volume_cm3"]) / float(r["alpha_wrap_volume_cm3"])
            dropped = [float(r["berries_removed_by_packing"]) / (float(r["berries"]) +
                       float(r["berries_removed_by_packing"])) for r in rows]
            print("| %s | %s | %s | %s | %s | %s%s | %s | %s | %.1f %% |" % (
                preset, name, cell(rows, "berries", "%.0f"), cell(rows, "solid_volume_cm3", "%.0f"),
                cell(rows, "compactness", "%.3f"), cell(rows, "solid_over_wrap", "%.3f") + " | " if wrap else "",
                cell(rows, "berries_in_contact", "%.2f"),
                cell(rows, "contact_depth_mean", "%.3f"), cell(rows, "contact_depth_max", "%.3f"),
                100 * statistics.mean(dropped)))
            sys.stdout.flush()


if __name__ == "__main__":
    main()
