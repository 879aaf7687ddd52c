#!/usr/bin/python3
"""Draw a grapebench dataset's COCO annotations over its images: each instance's
visible mask filled in a colour of its category (amodal outline dashed with --amodal),
its box, and a legend. Reads only the COCO JSON and the images (numpy and Debian's
python3-opencv), so it also checks that the files stand on their own.

usage: coco_view.py DATASET [--split train] [--images N] [--categories bunch,berry]
                    [--amodal] --out FOLDER
"""
import argparse
import json
import sys
from pathlib import Path

import cv2
import numpy as np

COLOURS = {"bunch": (180, 60, 200), "berry": (40, 200, 255), "stalk": (0, 0, 255), "leaf": (60, 220, 60),
           "cane": (30, 120, 200)}  # BGR


def rle_counts(s):
    """COCO's compressed RLE string to its runs (pycocotools' rleFrString, written from
    its description: 5-bit groups in characters 48..111, a continuation bit 0x20, the
    last group's 0x10 the sign; from the fourth run on, the difference to the run two
    before)."""
    counts = []
    p = 0
    while p < len(s):
        x, k, more = 0, 0, True
        while more:
            c = ord(s[p]) - 48
            if not 0 <= c <= 63:
                raise ValueError(f"character {p} of an RLE string is outside '0'..'o'")
            x |= (c & 0x1F) << (5 * k)
            more = bool(c & 0x20)
            p += 1
            k += 1
            if not more and c & 0x10:
                x |= -1 << (5 * k)
        if len(counts) > 2:
            x += counts[-2]
        counts.append(x)
    return counts


def rle_string(mask):
    """COCO's compressed RLE string of a bool h x w mask: the inverse of rle_counts."""
    flat = mask.T.reshape(-1).astype(np.uint8)
    change = np.flatnonzero(np.diff(np.concatenate([[0], flat, [1 - flat[-1]]])))
    runs = np.diff(np.concatenate([[0], change])).tolist()
    if runs and runs[-1] == 0:
        runs.pop()
    out = []
    for i, x in enumerate(runs):
        if i > 2:
            x -= runs[i - 2]
        while True:
            c = x & 0x1F
            x >>= 5
            more = x != -1 if c & 0x10 else x != 0
            if more:
                c |= 0x20
            out.append(chr(c + 48))
            if not more:
                break
    return "".join(out)


def rle_decode(segmentation):
    """A {size: [h, w], counts: str} mask as an h x w bool array."""
    h, w = segmentation["size"]
    flat = np.zeros(h * w, dtype=bool)
    at, value = 0, False
    for c in rle_counts(segmentation["counts"]):
        if c < 0:
            raise ValueError("negative run")
        if value:
            flat[at:at + c] = True
        at += c
        value = not value
    if at != h * w:
        raise ValueError(f"runs cover {at} pixels, the mask has {h * w}")
    return flat.reshape(w, h).T  # column-major


def draw(dataset, image, anns, names, amodal):
    picture = cv2.imread(str(dataset / image["file_name"]), cv2.IMREAD_COLOR)
    if picture is None:
        raise SystemExit(f"{dataset / image['file_name']}: unreadable")
    overlay = picture.copy()
    for a in sorted(anns, key=lambda a: -a["area"]):  # small instances on top
        name = names[a["category_id"]]
        colour = COLOURS.get(name, (255, 255, 255))
        overlay[rle_decode(a["segmentation"])] = colour
    out = cv2.addWeighted(picture, 0.45, overlay, 0.55, 0)
    for a in anns:
        name = names[a["category_id"]]
        colour = COLOURS.get(name, (255, 255, 255))
        x, y, w, h = a["bbox"]
        if name in ("bunch", "stalk"):
            cv2.rectangle(out, (int(x), int(y)), (int(x + w - 1), int(y + h - 1)), colour, 1)
        if amodal:
            m = rle_decode(a["amodal_segmentation"]).astype(np.uint8)
            contours, _ = cv2.findContours(m, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
            for c in contours:
                for i, p in enumerate(c[:, 0, :]):
                    if (i // 3) % 2 == 0:
                        out[p[1], p[0]] = colour
    scale = max(0.45, out.shape[1] / 700 * 0.45)  # the legend readable at any size
    thick = max(1, int(round(scale * 1.5)))
    y = int(30 * scale)
    for cid, name in names.items():
        cv2.putText(out, name, (6, y), cv2.FONT_HERSHEY_SIMPLEX, scale, COLOURS.get(name, (255, 255, 255)), thick,
                    cv2.LINE_AA)
        y += int(36 * scale)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset", type=Path)
    ap.add_argument("--split", default="train")
    ap.add_argument("--images", type=int, default=4, help="how many images (first ones)")
    ap.add_argument("--categories", default="", help="comma-separated names (default: all)")
    ap.add_argument("--amodal", action="store_true", help="also outline the amodal masks")
    ap.add_argument("--out", type=Path, required=True)
    args = ap.parse_args()
    coco = json.loads((args.dataset / "annotations" / f"{args.split}.json").read_text())
    names = {c["id"]: c["name"] for c in coco["categories"]}
    wanted = set(args.categories.split(",")) if args.categories else set(names.values())
    by_image = {}
    for a in coco["annotations"]:
        if names[a["category_id"]] in wanted:
            by_image.setdefault(a["image_id"], []).append(a)
    args.out.mkdir(parents=True, exist_ok=True)
    for image in coco["images"][:args.images]:
        out = draw(args.dataset, image, by_image.get(image["id"], []), names, args.amodal)
        path = args.out / Path(image["file_name"]).name
        cv2.imwrite(str(path), out)
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
