#!/usr/bin/python3
"""Validation table of the variety presets (docs/synth.md, "Variety presets").

Runs `grapebench synth --no-mesh` for each variety preset as it is and prints one
Markdown row per preset beside the published figures it was built from: berries, bunch
mass, length (vertical, without the peduncle), width (extent along the second principal
axis), solid / convex hull, solid / alpha wrap, berries in contact, the deepest contact,
the berries the packing dropped, the horizontal extent ratio and the wing's share of the
berries, each the mean over the bunches (sd in brackets).

    /usr/bin/python3 scripts/variety_presets_table.py build/bench/grapebench --count 16
"""
import os
import statistics

from oiv_compactness_table import cell, parser, run

# Published figures (docs/synth.md lists each source with its quote).
PUBLISHED = {
    "red-globe": ("650-850 g", "not found"),
    "cabernet-sauvignon": ("73-157 g", "12-15 x 7-8 cm"),
    "summer-black-ga": ("608 g (600-900)", "16-23 x 13.5-16 cm"),
    "italia": ("400-700 g (627)", "20-22 x 14 cm"),
}


def main():
    a = parser(__doc__, "results/variety_table").parse_args()
    print("| preset | berries | bunch mass g | published | length x width cm | published | solid / hull | "
          "solid / wrap | berries in contact | contact depth, max | dropped | horizontal extent ratio | "
          "wing share |")
    print("|---" * 13 + "|")
    for preset, (mass, size) in PUBLISHED.items():
        rows = run(a.grapebench, preset, [], a.count, a.seed, os.path.join(a.out, preset), a.alpha)
        for r in rows:
            r["solid_over_wrap"] = float(r["solid_volume_cm3"]) / float(r["alpha_wrap_volume_cm3"]) if a.alpha > 0 else 0
        dropped = [float(r["berries_removed_by_packing"]) / (float(r["berries"]) + float(r["berries_removed_by_packing"]))
                   for r in rows]
        print("| %s | %s | %s | %s | %s x %s | %s | %s | %s | %s | %s | %.1f %% | %s | %s |" % (
            preset, cell(rows, "berries", "%.0f"), cell(rows, "mass_g", "%.0f"), mass,
            cell(rows, "hanging_height_m", "%.1f", 100), cell(rows, "pca_length_m", "%.1f", 100), size,
            cell(rows, "compactness", "%.3f"), cell(rows, "solid_over_wrap", "%.3f") if a.alpha > 0 else "-",
            cell(rows, "berries_in_contact", "%.2f"), cell(rows, "contact_depth_max", "%.3f"),
            100 * statistics.mean(dropped), cell(rows, "horizontal_extent_ratio", "%.2f"),
            cell(rows, "wing_berry_share", "%.2f")))


if __name__ == "__main__":
    main()
