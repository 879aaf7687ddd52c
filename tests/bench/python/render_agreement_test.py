"""Issue 38, item 5's gate on a small subset: the fast `ray` renderer against Blender's
Cycles on three views of the validation set, one per variety and light (views 0, 13 and
26 of bench/perf/render_agreement.cpp), at 100 x 75 and 16 samples so that the test
costs about 30 s. The targets are the issue's: per-class mean CIEDE2000 at most 6,
luminance SSIM at least 0.85. The object-index pass must agree with the exact labels
(IoU 0.99 at 800 x 600 in docs/sensors.md; at 100 x 75 a stem is under a pixel wide,
so 0.97 here). Both sky strides are gated against the same Cycles images: 2, `ray`'s
default since 2026-12-07, and 1, the committed scenes'. Skipped (77) without Blender.

usage: render_agreement_test.py <grapebench_render_agreement> <scratch folder>
"""
import csv
import math
import shutil
import subprocess
import sys
from pathlib import Path


def main():
    exe, scratch = sys.argv[1], Path(sys.argv[2])
    if shutil.which("blender") is None:
        print("blender not installed (Debian package `blender`): skipped")
        return 77
    shutil.rmtree(scratch, ignore_errors=True)
    subprocess.run([exe, "--scale", "8", "--samples", "16", "--threads", "2", "--only", "0", "13", "26",
                    "--sky-stride", "2", "1", "--out", str(scratch)], check=True, stdout=subprocess.DEVNULL)
    with open(scratch / "agreement.csv") as f:
        rows = list(csv.DictReader(f))
    assert [(r["view"], r["sky_stride"]) for r in rows] == [
        (v, s) for v in ["0", "13", "26"] for s in ["2", "1"]], rows
    assert {r["variety"] for r in rows} == {"summer-black", "table-red", "green-table"}, rows
    failures = []
    for r in rows:
        name = f"view {r['view']} ({r['variety']}, {r['light']}, {r['distance_m']} m, sky_stride {r['sky_stride']})"
        for key in ["de_berry", "de_stem", "de_foliage", "de_background"]:
            x = float(r[key])
            if math.isnan(x):
                continue  # fewer than 20 pixels of the class
            if not x <= 6:
                failures.append(f"{name}: {key} {x} > 6")
        if not float(r["ssim"]) >= 0.85:
            failures.append(f"{name}: ssim {r['ssim']} < 0.85")
        for key in ["iou_berry", "iou_stem", "iou_foliage"]:
            x = float(r[key])
            if not math.isnan(x) and not x >= 0.97:
                failures.append(f"{name}: {key} {x} < 0.97")
        # Every view scored something: a renderer that drew nothing would pass the rest.
        assert not math.isnan(float(r["de_berry"])), name
        # The boundary gradients' distributions were compared (no target: docs/sensors.md).
        assert 0 <= float(r["grad_ks"]) <= 1, (name, r["grad_ks"])
    for line in failures:
        print(line)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
