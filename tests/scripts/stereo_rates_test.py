#!/usr/bin/python3
"""scripts/stereo_rates.py's intervals: the pair-unit ratio interval against a hand
computation, and wider than Wilson's when a pair's berries come all or none."""
import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import stereo_rates  # noqa: E402


class Intervals(unittest.TestCase):
    def test_the_ratio_interval_is_cochrans(self):
        # R = 25 / 100; residuals f - R v = -2, -1, 0, 1, 2; se = sqrt(5 / 4 * 10) / 100;
        # t(4) = 2.776: 25.0 (15.2-34.8).
        r, lo, hi = stereo_rates.ratio_bounds([3, 4, 5, 6, 7], [20] * 5)
        self.assertAlmostEqual(r, 25.0)
        self.assertAlmostEqual(lo, 25.0 - 2.776 * 100 * (12.5 ** 0.5) / 100, places=6)
        self.assertAlmostEqual(hi, 25.0 + 2.776 * 100 * (12.5 ** 0.5) / 100, places=6)
        self.assertEqual(stereo_rates.ratio_interval([3, 4, 5, 6, 7], [20] * 5), "25.0 (15.2-34.8)")

    def test_all_or_none_pairs_widen_it_past_wilsons(self):
        # 32 pairs of 25 berries, every third pair's cut matched (all its berries found
        # at 40 %), the rest none: Wilson treats the 800 berries as independent draws.
        found = [10 if i % 3 == 0 else 0 for i in range(32)]
        visible = [25] * 32
        _, wlo, whi = stereo_rates.wilson_bounds(sum(found), sum(visible))
        _, rlo, rhi = stereo_rates.ratio_bounds(found, visible)
        self.assertGreater(rhi - rlo, 2.5 * (whi - wlo))

    def test_too_few_pairs_no_berry_or_no_spread_give_no_interval(self):
        self.assertIsNone(stereo_rates.ratio_bounds([3], [20]))
        self.assertIsNone(stereo_rates.ratio_bounds([0, 0], [0, 0]))
        # Every pair at the same rate: a variance estimate of 0, not an interval of width 0.
        self.assertIsNone(stereo_rates.ratio_bounds([0, 0, 0], [20, 25, 30]))
        self.assertIsNone(stereo_rates.ratio_bounds([2, 4], [10, 20]))
        self.assertIsNone(stereo_rates.wilson_bounds(0, 0))
        self.assertEqual(stereo_rates.ratio_interval([0, 0], [0, 0]), "-")


if __name__ == "__main__":
    unittest.main()
