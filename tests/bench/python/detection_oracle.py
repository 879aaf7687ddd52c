#!/usr/bin/python3
"""A test-only external estimator for protocol detection (input: image) that knows the
answer from outside the harness: it finds the request's image among the images of a
dataset written by `grapebench dataset` from the same scene (equal pixels) and answers
that image's annotations as instances. Through the protocol they must score AP 1, so
the protocol's truth, the dataset writer's and the answer's path through the external
protocol agree. The harness never hands it labels; it reads them from the dataset.

usage: detection_oracle.py DATASET REQUEST      (per-case mode)
       detection_oracle.py DATASET --persistent (JSON lines on stdin and stdout)
"""
import json
import sys
from pathlib import Path

import cv2
import numpy as np


def load(dataset):
    cats = None
    images = []
    for split in ("train", "val", "test"):
        coco = json.loads((dataset / "annotations" / f"{split}.json").read_text())
        cats = {c["id"]: c["name"] for c in coco["categories"]}
        by_image = {}
        for a in coco["annotations"]:
            by_image.setdefault(a["image_id"], []).append(a)
        for im in coco["images"]:
            pixels = cv2.imread(str(dataset / im["file_name"]), cv2.IMREAD_COLOR)
            images.append((pixels, by_image.get(im["id"], [])))
    return cats, images


def reply_to(req, cats, images):
    left = cv2.imread(req["image"]["left"], cv2.IMREAD_COLOR)
    found = [anns for pixels, anns in images if pixels.shape == left.shape and np.array_equal(pixels, left)]
    if len(found) != 1:
        return {"error": f"the image matches {len(found)} dataset images"}
    return {"instances": [{"category": cats[a["category_id"]], "score": 1.0, "bbox": a["bbox"],
                           "segmentation": a["segmentation"]} for a in found[0]]}


def main():
    dataset = Path(sys.argv[1])
    cats, images = load(dataset)
    if sys.argv[2] == "--persistent":
        for line in sys.stdin:
            sys.stdout.write(json.dumps(reply_to(json.loads(line), cats, images)) + "\n")
            sys.stdout.flush()
        return
    req = json.loads(Path(sys.argv[2]).read_text())
    Path(req["answer"]).write_text(json.dumps(reply_to(req, cats, images)))


if __name__ == "__main__":
    main()
