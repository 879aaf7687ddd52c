#!/usr/bin/python3
"""scripts/pixel_noise.py: the spread about the 3 x 3 median of a flat field with known
white noise, per class and channel; class edges left out; bad input exits 2."""
import os
import subprocess
import sys
import tempfile
import unittest

import cv2
import numpy as np

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "pixel_noise.py")
sys.path.insert(0, os.path.dirname(SCRIPT))
import pixel_noise  # noqa: E402


class Spread(unittest.TestCase):
    def test_known_noise_per_class_and_channel(self):
        rng = np.random.default_rng(3)
        h, w = 200, 300
        label = np.full((h, w), 5, np.uint8)  # leaves
        label[:, :150] = 0  # berries on the left half
        rgb = np.empty((h, w, 3))
        rgb[..., 0], rgb[..., 1], rgb[..., 2] = 60, 120, 40
        rgb[:, 150:, 1] = 200  # a step at the class edge: edges must not count
        sd = np.where(label[..., None] == 0, [2.0, 6.0, 4.0], [0.0, 3.0, 0.0])
        noisy = np.clip(np.round(rgb + sd * rng.standard_normal((h, w, 3))), 0, 255).astype(np.uint8)
        with tempfile.TemporaryDirectory() as d:
            cv2.imwrite(os.path.join(d, "v_left.png"), noisy[..., ::-1])
            cv2.imwrite(os.path.join(d, "v_label.png"), label)
            s = pixel_noise.spread(d)
        n, berries = s["berries"]
        self.assertEqual(n, (h - 2) * (150 - 2))  # inner pixels only
        # About a 3 x 3 median, white noise of sd s leaves a spread of 0.97-0.99 s
        # (measured on flat fields of s = 2-10 DN, rounded to 8 bits).
        for got, want in zip(berries, [2.0, 6.0, 4.0]):
            self.assertAlmostEqual(got / want, 0.98, delta=0.04)
        _, leaves = s["leaves"]
        self.assertAlmostEqual(leaves[1] / 3.0, 0.98, delta=0.04)
        self.assertLess(leaves[0], 0.05)  # no noise, no edge: nothing
        self.assertEqual(s["stems and canes"][0], 0)

    def test_bad_input_exits_2(self):
        with tempfile.TemporaryDirectory() as d:
            p = subprocess.run(["/usr/bin/python3", SCRIPT, d], capture_output=True, text=True)
            self.assertEqual(p.returncode, 2)
            self.assertIn("no *_left.png", p.stderr)
            cv2.imwrite(os.path.join(d, "v_left.png"), np.zeros((4, 4, 3), np.uint8))
            p = subprocess.run(["/usr/bin/python3", SCRIPT, d], capture_output=True, text=True)
            self.assertEqual(p.returncode, 2)
            self.assertIn("v_left.png", p.stderr)


if __name__ == "__main__":
    unittest.main()
