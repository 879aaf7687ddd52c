#!/usr/bin/python3
"""scripts/cut_ez_split.py: Fig. 11's mean |e_z| split into the gross errors on and off
the stalk, against a hand count of a small results.csv."""
import csv
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import cut_ez_split  # noqa: E402

COLUMNS = ["scene", "condition", "seed", "frame", "estimator", "quantity", "estimate", "truth", "error", "roi", "ok", "message"]


def rows():
    # (bunch, station mm, e_z mm or None for no cut, axis distance mm)
    pairs = [(0, 490, 1.0, 150.0), (1, 490, -2.0, 2.0), (2, 510, 3.0, 4.0), (3, 510, -140.0, 3.0),
             (4, 530, 200.0, 180.0), (5, 530, None, None), (6, 880, 0.5, 1.0)]
    for b, st, ez, ax in pairs:
        roi = "station_%04dmm" % st
        est = "NaN" if ez is None else str(st + ez)
        yield ["s", "light=front", b, 0, "luo_eq6", "cut_z", est, str(st), "NaN" if ez is None else str(ez), roi, "1", ""]
        yield ["s", "light=front", b, 0, "luo_eq6", "cut_axis_distance", "NaN" if ax is None else str(ax), "0", "", roi, "1", ""]
        # another estimator's rows are not counted
        yield ["s", "light=front", b, 0, "luo_pinhole", "cut_z", str(st + 500), str(st), "500", roi, "1", ""]


class Split(unittest.TestCase):
    def test_the_bins_counts_and_means_are_the_hand_count(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "results.csv")
            with open(path, "w", newline="") as f:
                w = csv.writer(f)
                w.writerow(COLUMNS)
                w.writerows(rows())
            got = cut_ez_split.split(cut_ez_split.load([path], "luo_eq6"), gross=30, on_stalk=10)
        self.assertEqual([r[0] for r in got], [500, 900])
        b, n, mean, med, on, off, share, wo_on, wo = got[0]
        self.assertEqual((n, on, off), (5, 1, 1))  # the -140 on the stalk (3 mm), the 200 off it (180 mm)
        self.assertAlmostEqual(mean, (1 + 2 + 3 + 140 + 200) / 5)
        self.assertAlmostEqual(med, 3)
        self.assertAlmostEqual(share, 340 / 346)
        self.assertAlmostEqual(wo_on, (1 + 2 + 3 + 200) / 4)
        self.assertAlmostEqual(wo, 2)
        self.assertEqual(got[1][1:7], (1, 0.5, 0.5, 0, 0, 0.0))


if __name__ == "__main__":
    unittest.main()
