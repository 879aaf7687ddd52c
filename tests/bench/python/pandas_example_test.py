"""The README's pandas example runs on a fresh default-suite run, and keeps the seeds
exact (64-bit unsigned values above 2^63 read back unchanged).

usage: pandas_example_test.py <grapebench> <README.md> <scenes/default.yaml> <scratch folder>
"""
import csv
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pandas as pd


def main():
    exe, readme, scene, scratch = sys.argv[1], Path(sys.argv[2]), sys.argv[3], Path(sys.argv[4])
    shutil.rmtree(scratch, ignore_errors=True)
    subprocess.run([exe, "run", scene, "-q", "--out", str(scratch / "results" / "runs")], check=True,
                   stdout=subprocess.DEVNULL)
    text = readme.read_text()
    block = re.search(r"<!-- pandas-example.*?-->\s*```python\n(.*?)```", text, re.S)
    assert block, "no pandas example in the README"
    out = subprocess.run([sys.executable, "-c", block.group(1)], cwd=scratch, check=True, capture_output=True,
                         text=True)
    assert "VB_5mm" in out.stdout and "count" in out.stdout, out.stdout
    path = scratch / "results" / "runs" / "default" / "results.csv"
    with open(path) as f:
        exact = [int(r["seed"]) for r in csv.DictReader(f)]
    read = pd.read_csv(path, dtype={"seed": "uint64"})["seed"].tolist()
    assert [int(x) for x in read] == exact
    assert max(exact) > 2**63, "the run has no seed above 2^63 to check"
    print(out.stdout)


if __name__ == "__main__":
    main()
