#!/usr/bin/env python3
"""Seed 000's Table 1 layout from a grapebench run's results.csv (standard library only).

Usage: scripts/seed000_table1.py results/runs/seed000_true_poses/results.csv
Rows: one per bunch (true volume, GM, CH, AS, VB, PB in cm3; E_l, E_w, E_h in mm as
estimate - truth), then R2 and RMSE per method from summary.json beside it. When the
run measured the rig's visibility hull (pipeline.visibility_hull), a last volume
column "floor" gives it: the least volume an estimator that invents no geometry can
report from these views.
"""
import csv
import json
import os
import sys

path = sys.argv[1]
rows = list(csv.DictReader(open(path)))
summary = json.load(open(os.path.join(os.path.dirname(path), "summary.json")))
vol = ["GM", "CH", "AS", "VB", "PB"]
by = {}
for r in rows:
    by.setdefault(int(r["bunch"]), {})[(r["estimator"], r["quantity"])] = r
if any(r["estimator"] == "visibility_hull" for r in rows):
    vol.append("visibility_hull")
heads = ["floor" if m == "visibility_hull" else m for m in vol]
print("| bunch | true V (cm3) | " + " | ".join(heads) + " | E_l (mm) | E_w (mm) | E_h (mm) |")
print("|" + "---|" * (5 + len(vol)))
for b in sorted(by):
    d = by[b]
    true_v = float(d[("CH", "volume")]["truth"])
    cells = ["%.0f" % float(d[(m, "volume")]["estimate"]) if d[(m, "volume")]["ok"] == "1" else "fail" for m in vol]
    errs = ["%+.1f" % float(d[("PCA_box", q)]["error"]) for q in ("length", "width", "height")]
    print("| %d | %.0f | %s | %s |" % (b + 1, true_v, " | ".join(cells), " | ".join(errs)))
s = {(x["estimator"], x["quantity"]): x for x in summary["scores"]}
print("| **R2** | | " + " | ".join("%.3f" % s[(m, "volume")]["r2"] for m in vol) + " | " +
      " | ".join("%.3f" % s[("PCA_box", q)]["r2"] for q in ("length", "width", "height")) + " |")
print("| **RMSE** | | " + " | ".join("%.0f" % s[(m, "volume")]["rmse"] for m in vol) + " | " +
      " | ".join("%.1f" % s[("PCA_box", q)]["rmse"] for q in ("length", "width", "height")) + " |")
print("| **bias** | | " + " | ".join("%+.0f" % s[(m, "volume")]["bias"] for m in vol) + " | " +
      " | ".join("%+.1f" % s[("PCA_box", q)]["bias"] for q in ("length", "width", "height")) + " |")
