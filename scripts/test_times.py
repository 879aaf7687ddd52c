#!/usr/bin/python3
"""The closing tables of scripts/test.sh: each stage's wall time, and the 15 slowest
tests of the ctest JUnit files given (name, stage, seconds).

Usage: test_times.py STAGES.tsv [ctest-junit.xml ...]
STAGES.tsv: one `stage<TAB>seconds` a line, in order.
"""
import os
import sys
import xml.etree.ElementTree as ET


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    stages = []
    if os.path.exists(argv[1]):
        with open(argv[1], encoding="utf-8") as f:
            for line in f:
                name, _, sec = line.rstrip("\n").rpartition("\t")
                if name:
                    stages.append((name, int(sec)))
    total = sum(s for _, s in stages)
    print("\n== stage times (wall)")
    width = max([len(n) for n, _ in stages] + [5])
    for name, sec in stages:
        print(f"  {name:<{width}}  {sec:>6d} s  {sec / 60:6.1f} min")
    print(f"  {'total':<{width}}  {total:>6d} s  {total / 60:6.1f} min")

    tests = []
    for path in argv[2:]:
        if not os.path.exists(path):
            continue
        label = os.path.splitext(os.path.basename(path))[0]
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError as e:
            print(f"  ({path}: not readable JUnit: {e})")
            continue
        for case in root.iter("testcase"):
            try:
                sec = float(case.get("time", "0"))
            except ValueError:
                continue
            status = case.get("status", "")
            tests.append((sec, case.get("name", "?"), label, status))
    if tests:
        tests.sort(reverse=True)
        busy = sum(t[0] for t in tests)
        print(f"\n== the 15 slowest of {len(tests)} tests ({busy:.0f} test-seconds in all)")
        for sec, name, label, status in tests[:15]:
            mark = "" if status in ("run", "") else f"  [{status}]"
            print(f"  {sec:8.1f} s  {label:<8} {name}{mark}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
