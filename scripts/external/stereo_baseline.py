#!/usr/bin/env python3
"""A grapebench external estimator of a colour stereo pair, in numpy (Debian:
python3-numpy; PNG files read with python3-open3d). A deliberately simple baseline
beside seed 001's system, to show the stereo_pair request and the point answer.

Request (protocol grapebench-estimator-2, kind stereo_pair; docs/external-protocol.schema.json):
"stereo" names left.png and right.png (8-bit RGB, rectified) with fx, fy, cx, cy
(pixels, OpenCV's convention: pixel (x, y) has its centre at (x, y)) and the baseline
(m). The answer holds the point "cutting_point" (left camera frame, m) and each
requested quantity (here hanging_height, m).

Method: grape pixels are those whose green is below both red and blue (purple or red
berries against green leaves); the cluster is the widest run of such rows; the
cutting point is 12 px above its top row, at the mean column of its top rows; its
disparity is the best zero-mean NCC of a 9 x 9 window over the disparities of
0.35-1.1 m; the height is the cluster's pixel height at that depth.
"""
import argparse
import json
import sys

import numpy as np
import open3d as o3d

WINDOW = 4  # half of the 9 x 9 window


def read_rgb(path):
    image = np.asarray(o3d.io.read_image(path))
    if image.ndim != 3 or image.shape[2] < 3:
        raise ValueError("%s: not an RGB image" % path)
    return image[:, :, :3].astype(np.float64)


def grape_rows(left):
    r, g, b = left[:, :, 0], left[:, :, 1], left[:, :, 2]
    mask = (g + 8 < r) & (g + 8 < b)
    rows = np.nonzero(mask.sum(axis=1) >= 6)[0]
    if rows.size == 0:
        raise ValueError("no grape-coloured pixels")
    return mask, rows


def ncc_disparity(left, right, x, y, d_lo, d_hi):
    grey_l, grey_r = left.mean(axis=2), right.mean(axis=2)
    h, w = grey_l.shape
    if y - WINDOW < 0 or y + WINDOW >= h or x - WINDOW < 0 or x + WINDOW >= w:
        raise ValueError("the cutting point's window leaves the image")
    t = grey_l[y - WINDOW:y + WINDOW + 1, x - WINDOW:x + WINDOW + 1]
    t = t - t.mean()
    best, best_d = -2.0, None
    for d in range(d_lo, d_hi + 1):
        xr = x - d
        if xr - WINDOW < 0:
            break
        s = grey_r[y - WINDOW:y + WINDOW + 1, xr - WINDOW:xr + WINDOW + 1]
        s = s - s.mean()
        den = np.sqrt((t * t).sum() * (s * s).sum())
        score = (t * s).sum() / den if den > 0 else -1.0
        if score > best:
            best, best_d = score, d
    if best_d is None:
        raise ValueError("no disparity to search")
    return best_d, best


def answer(req):
    if req.get("kind") != "stereo_pair":
        raise ValueError("this program measures stereo pairs (input: stereo_pair in the scene)")
    s = req["stereo"]
    left, right = read_rgb(s["left"]), read_rgb(s["right"])
    mask, rows = grape_rows(left)
    top, bottom = int(rows.min()), int(rows.max())
    cols = np.nonzero(mask[top:top + 5].any(axis=0))[0]
    x, y = int(round(cols.mean())), max(WINDOW, top - 12)
    fb = s["fx"] * s["baseline"]
    d, score = ncc_disparity(left, right, x, y, int(fb / 1.1), int(np.ceil(fb / 0.35)))
    z = fb / d
    point = [(x - s["cx"]) * z / s["fx"], (y - s["cy"]) * z / s["fy"], z]
    reply = {"points": {"cutting_point": point}, "notes": "disparity %d px, NCC %.3f" % (d, score)}
    if "hanging_height" in req["quantities"]:
        reply["hanging_height"] = (bottom - top + 1) * z / s["fy"]
    return reply


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--persistent", action="store_true", help="answer JSON lines on stdin, one line each on stdout")
    ap.add_argument("request", nargs="?", help="the request file (per-case mode)")
    args = ap.parse_args()
    if args.persistent:
        for line in sys.stdin:
            try:
                reply = answer(json.loads(line))
            except Exception as e:  # noqa: BLE001 - reported to the harness, which fails that row
                reply = {"error": str(e)}
            sys.stdout.write(json.dumps(reply) + "\n")
            sys.stdout.flush()
        return
    if not args.request:
        ap.error("a request file, or --persistent")
    with open(args.request) as f:
        req = json.load(f)
    try:
        reply = answer(req)
    except ValueError as e:
        reply = {"error": str(e)}
    with open(req["answer"], "w") as f:
        json.dump(reply, f)


if __name__ == "__main__":
    main()
