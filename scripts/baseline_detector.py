#!/usr/bin/python3
"""A classical detector baseline for grapebench datasets, as an external program: it reads
only a split's images and their intrinsics (the COCO JSON's `images`), never the labels,
and writes COCO results for `grapebench coco-eval`.

- bunches: seed 001's colour segmentation (Luo et al. 2016, Sect. 2.2.2.1): the H - I
  component (HSI hue minus intensity), Otsu's threshold, a 3 x 3 dilation, regions of at
  least `--min-region` px; each region a bunch with its mask, scored by its area;
- berries: seed 001's circle detection (Sect. 2.2.2.4) inside the bunch regions: Gaussian
  blur, OpenCV's Hough gradient (param1 60, param2 13), the radius window of 8-20 mm
  berries at the `--depth` range through the image's focal length; scored by rank.

usage: baseline_detector.py DATASET --split test --out results.json
       baseline_detector.py --request REQUEST.json | --persistent   (an external estimator
       of protocol detection: `{type: external, version: 2, input: image, command: [...]}`)
"""
import argparse
import json
import math
import sys
from pathlib import Path

import cv2
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from coco_view import rle_string  # noqa: E402  (the datasets' RLE, both ways)


def hue_minus_intensity(bgr):
    """Seed 001's component for dark varieties: H of HSI in [0, 1] minus I, to 0..255."""
    f = bgr.astype(np.float64) / 255.0
    b, g, r = f[..., 0], f[..., 1], f[..., 2]
    num = 0.5 * ((r - g) + (r - b))
    den = np.sqrt((r - g) ** 2 + (r - b) * (g - b)) + 1e-12
    theta = np.arccos(np.clip(num / den, -1, 1))
    h = np.where(b > g, 2 * math.pi - theta, theta) / (2 * math.pi)
    i = (r + g + b) / 3
    return np.clip((h - i + 1) * 127.5, 0, 255).astype(np.uint8)


def bunch_rank(c, bunches):
    for i, (m, _, _) in enumerate(bunches):
        if m[min(int(c[1]), m.shape[0] - 1), min(int(c[0]), m.shape[1] - 1)]:
            return i
    return len(bunches)


def detect(bgr, fx, args):
    comp = hue_minus_intensity(bgr)
    _, mask = cv2.threshold(comp, 0, 255, cv2.THRESH_BINARY + cv2.THRESH_OTSU)
    mask = cv2.dilate(mask, np.ones((3, 3), np.uint8))
    n, labels, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=8)
    bunches = []
    for k in range(1, n):
        x, y, w, h, area = stats[k]
        if area >= args.min_region:
            bunches.append((labels == k, [int(x), int(y), int(w), int(h)], float(area)))
    bunches.sort(key=lambda b: -b[2])
    bunches = bunches[:args.max_bunches]
    grey = cv2.GaussianBlur(cv2.cvtColor(bgr, cv2.COLOR_BGR2GRAY), (0, 0), 1.0)
    r_min = max(2, int(fx * 0.008 / args.depth[1]))
    r_max = int(math.ceil(fx * 0.020 / args.depth[0]))
    berries = []
    for m, (x, y, w, h), _ in bunches:  # Hough inside each region's box (the paper's ROI)
        x0, y0 = max(0, x - r_max), max(0, y - r_max)
        crop = grey[y0:y + h + r_max, x0:x + w + r_max]
        circles = cv2.HoughCircles(crop, cv2.HOUGH_GRADIENT, dp=1, minDist=r_min, param1=60, param2=13,
                                   minRadius=r_min, maxRadius=r_max)
        for cx, cy, r in ([] if circles is None else circles[0]):
            u, v = int(cx) + x0, int(cy) + y0
            if 0 <= v < m.shape[0] and 0 <= u < m.shape[1] and m[v, u]:
                berries.append((float(cx) + x0, float(cy) + y0, float(r)))
    berries.sort(key=lambda c: bunch_rank(c, bunches))  # the largest region's first, Hough's order within
    return bunches, berries


def image_results(bgr, fx, args):
    """COCO results of one image, without image ids: (category id, score, box, mask)."""
    bunches, berries = detect(bgr, fx, args)
    h, w = bgr.shape[:2]
    out = [(1, area / (h * w), box, m) for m, box, area in bunches]
    for rank, (cx, cy, r) in enumerate(berries[:args.max_berries]):
        disc = np.zeros((h, w), np.uint8)
        cv2.circle(disc, (int(round(cx)), int(round(cy))), int(round(r)), 1, -1)
        ys, xs = np.nonzero(disc)
        if xs.size == 0:
            continue
        box = [int(xs.min()), int(ys.min()), int(xs.max() - xs.min() + 1), int(ys.max() - ys.min() + 1)]
        out.append((2, 1.0 / (1 + rank), box, disc.astype(bool)))
    return out, len(bunches), len(berries)


def reply_to(req, args):
    """The external protocol's answer to one request (docs/external-protocol.schema.json, kind image)."""
    try:
        if req.get("kind") != "image":
            raise ValueError("this program measures images (input: image, protocol detection)")
        bgr = cv2.imread(req["image"]["left"], cv2.IMREAD_COLOR)
        if bgr is None:
            raise ValueError("unreadable image")
        results, nb, nr = image_results(bgr, req["image"]["fx"], args)
        h, w = bgr.shape[:2]
        names = {1: "bunch", 2: "berry"}
        reply = {"instances": [{"category": names[c], "score": s, "bbox": box,
                                "segmentation": {"size": [h, w], "counts": rle_string(m)}}
                               for c, s, box, m in results],
                 "notes": f"{nb} regions, {nr} circles"}
    except ValueError as e:
        reply = {"error": str(e)}
    return reply


def answer_requests(args):
    if args.persistent:
        for line in sys.stdin:
            sys.stdout.write(json.dumps(reply_to(json.loads(line), args)) + "\n")
            sys.stdout.flush()
        return 0
    req = json.loads(Path(args.request).read_text())
    Path(req["answer"]).write_text(json.dumps(reply_to(req, args)))
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset", type=Path, nargs="?")
    ap.add_argument("--split", default="test")
    ap.add_argument("--out", type=Path)
    ap.add_argument("--request", type=Path, help="answer one request of grapebench's external protocol")
    ap.add_argument("--persistent", action="store_true",
                    help="answer the external protocol's requests as JSON lines on stdin (persistent: true)")
    ap.add_argument("--min-region", type=int, default=400, help="px (seed 001's minimum cluster, 400 px)")
    ap.add_argument("--max-bunches", type=int, default=20)
    ap.add_argument("--max-berries", type=int, default=300, help="per image, the strongest Hough circles")
    ap.add_argument("--depth", type=float, nargs=2, default=[0.8, 1.8], help="m, the distance range assumed")
    args = ap.parse_args()
    if args.request or args.persistent:
        return answer_requests(args)
    if not args.dataset or not args.out:
        ap.error("DATASET and --out, or --request")
    coco = json.loads((args.dataset / "annotations" / f"{args.split}.json").read_text())
    results = []
    for im in coco["images"]:
        bgr = cv2.imread(str(args.dataset / im["file_name"]), cv2.IMREAD_COLOR)
        if bgr is None:
            raise SystemExit(f"{im['file_name']}: unreadable")
        found, nb, nr = image_results(bgr, im["intrinsics"]["fx"], args)
        h, w = bgr.shape[:2]
        for c, s, box, m in found:
            results.append({"image_id": im["id"], "category_id": c, "score": s, "bbox": box,
                            "segmentation": {"size": [h, w], "counts": rle_string(m)}})
        print(f"{im['file_name']}: {nb} bunches, {nr} berries", file=sys.stderr)
    args.out.write_text(json.dumps(results))
    return 0


if __name__ == "__main__":
    sys.exit(main())
