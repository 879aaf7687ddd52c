#!/usr/bin/python3
"""scripts/auc_draws.py: the pooled spread and the difference's interval against a hand
computation; two files under one label are one group's draws; bad input exits 2."""
import contextlib
import io
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "scripts", "auc_draws.py")
sys.path.insert(0, os.path.dirname(SCRIPT))
import auc_draws  # noqa: E402

HEADER = "scene,condition,sensor.camera.sky_samples,sensor.noise_seed,estimator,quantity,estimate\n"


def write(folder, name, rows):
    path = os.path.join(folder, name)
    with open(path, "w") as fh:
        fh.write(HEADER + "".join(rows))
    return path


def row(scene, k, draw, estimate, estimator="s2"):
    return "%s,sky_samples=%d noise_seed=%d,%d,%d,%s,auc_berry,%r\n" % (scene, k, draw, k, draw, estimator, estimate)


class Draws(unittest.TestCase):
    def test_pooled_spread_and_interval_by_hand(self):
        with tempfile.TemporaryDirectory() as d:
            # Group A: 0.70, 0.72, 0.74 (variance 4e-4); group B: 0.80, 0.84 (variance 8e-4).
            ray = write(d, "ray.csv", [row("ray", 1, s, v) for s, v in enumerate([0.70, 0.72, 0.74])])
            c0 = write(d, "c0.csv", [row("cyc", 1, 0, 0.80)])
            c1 = write(d, "c1.csv", [row("cyc_redrawn", 1, 1, 0.84)])
            groups = auc_draws.read([ray, "cycles=" + c0, "cycles=" + c1], "sensor.noise_seed", "auc_berry", [])
            self.assertEqual(list(groups), ["ray: sky_samples=1", "cycles"])
            self.assertEqual(sorted(groups["cycles"]["s2"].values()), [0.80, 0.84])
            s, df = auc_draws.pooled(groups, "s2")
            self.assertEqual(df, 3)  # 2 + 1
            self.assertAlmostEqual(s, ((4e-4 * 2 + 8e-4 * 1) / 3) ** 0.5)
            diff, half = auc_draws.difference([0.70, 0.72, 0.74], [0.80, 0.84], (s, df))
            self.assertAlmostEqual(diff, -0.10)
            self.assertAlmostEqual(half, 3.182 * s * (1 / 3 + 1 / 2) ** 0.5)
            out = io.StringIO()
            with contextlib.redirect_stdout(out):
                sys.argv = ["auc_draws.py", ray, "cycles=" + c0, "cycles=" + c1, "--against", "cycles"]
                auc_draws.main()
            self.assertIn("| ray: sky_samples=1 | -0.100 [", out.getvalue())
            self.assertIn("| pooled sd (degrees of freedom) | | 0.0231 (3) |", out.getvalue())

    def test_an_undefined_draw_is_counted_not_averaged(self):
        # Found on a 320 x 240 section where some draws scored no berry point: the
        # script raised AttributeError out of statistics.stdev on the nan.
        with tempfile.TemporaryDirectory() as d:
            ray = write(d, "ray.csv", [row("ray", 1, s, v) for s, v in enumerate([0.70, float("nan"), 0.74])])
            cyc = write(d, "cyc.csv", [row("cyc", 1, s, v) for s, v in enumerate([0.80, 0.84])])
            p = subprocess.run(["/usr/bin/python3", SCRIPT, ray, "cycles=" + cyc, "--against", "cycles"],
                               capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn("| ray: sky_samples=1 | 3 | 0.720 (0.028), 1 undefined |", p.stdout)
            self.assertIn("| ray: sky_samples=1 | -0.100 [", p.stdout)  # the two defined draws

    def test_bad_input_exits_2_naming_the_file(self):
        with tempfile.TemporaryDirectory() as d:
            twice = write(d, "twice.csv", [row("ray", 1, 0, 0.7), row("ray", 1, 0, 0.8)])
            empty = write(d, "empty.csv", [])
            ok = write(d, "a=b.csv", [row("ray", 1, 0, 0.7)])  # a "=" in a file's name
            for args, words in (([os.path.join(d, "missing.csv")], "missing.csv"), ([twice], "two rows"),
                                ([empty], "no rows"), ([ok, "--against", "x"], "is not a group")):
                p = subprocess.run(["/usr/bin/python3", SCRIPT] + args, capture_output=True, text=True)
                self.assertEqual(p.returncode, 2, args)
                self.assertIn(words, p.stderr)


if __name__ == "__main__":
    unittest.main()
