#!/usr/bin/python3
"""Pixel noise of colour images per class: the standard deviation, in 8-bit steps (DN),
of each channel about its 3 x 3 median, over the pixels of a class whose 3 x 3
neighbourhood is all that class (so edges and other classes do not count), from the
folders `grapebench scan` writes (<view>_left.png beside <view>_label.png, the exact
labels). docs/seed004.md, "Against Cycles": the renderers' own noise on the berries.

    /usr/bin/python3 scripts/pixel_noise.py results/scans/NAME/bunch_0000 [more folders]
"""
import argparse
import pathlib
import sys

import cv2
import numpy as np

CLASSES = {"berries": [0], "leaves": [5], "stems and canes": [1, 2, 3, 6]}


def fail(message):
    print("pixel_noise.py: " + message, file=sys.stderr)
    sys.exit(2)


def spread(folder):
    """{class: (pixels, [sd red, green, blue])} over every left image in `folder`."""
    diffs = {c: [] for c in CLASSES}
    lefts = sorted(pathlib.Path(folder).glob("*_left.png"))
    if not lefts:
        fail("%s: no *_left.png (a `grapebench scan` folder of a colour sensor?)" % folder)
    for left in lefts:
        label_path = pathlib.Path(str(left).replace("_left.png", "_label.png"))
        image = cv2.imread(str(left), cv2.IMREAD_COLOR)
        label = cv2.imread(str(label_path), cv2.IMREAD_UNCHANGED)
        if image is None or label is None:
            fail("%s: unreadable, or %s missing" % (left, label_path.name))
        if label.shape != image.shape[:2]:
            fail("%s: label %s against image %s" % (label_path, label.shape, image.shape[:2]))
        residual = image.astype(np.int16) - cv2.medianBlur(image, 3).astype(np.int16)
        for c, ids in CLASSES.items():
            mask = np.isin(label, ids).astype(np.uint8)
            inner = cv2.erode(mask, np.ones((3, 3), np.uint8), borderType=cv2.BORDER_CONSTANT, borderValue=0) > 0
            diffs[c].append(residual[inner][:, ::-1])  # BGR to RGB
    out = {}
    for c, parts in diffs.items():
        r = np.concatenate(parts) if parts else np.zeros((0, 3))
        out[c] = (len(r), [float(np.std(r[:, k])) if len(r) else float("nan") for k in range(3)])
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folders", nargs="+")
    a = ap.parse_args()
    print("| folder | " + " | ".join("%s: pixels, sd R / G / B (DN)" % c for c in CLASSES) + " |")
    print("|---|" + "---|" * len(CLASSES))
    for f in a.folders:
        s = spread(f)
        print("| %s | %s |" % (f, " | ".join("%d, %.1f / %.1f / %.1f" % (n, *sd) for n, sd in s.values())))


if __name__ == "__main__":
    main()
