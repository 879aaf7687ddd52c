"""`grapebench dataset` (issue 42) read back as a training script would: every file at 1
and 2 threads byte-identical; splits without a bunch in two of them; each COCO mask
(decoded by scripts/coco_view.py's own RLE reader) equal to the instance image's pixels,
inside its amodal mask, with its area and box; annotations linked to a 3D truth that
projects into them; YOLO lines matching the boxes; a folder that holds files refused,
another scene's never mixed in, and an interrupted dataset resumed to the same files; a
camera that stores JPEG writes its own .jpg files.

usage: dataset_test.py <grapebench> <scene.yaml> <coco_view.py> <scratch folder>
"""
import filecmp
import importlib.util
import json
import shutil
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np


def run(exe, *args, expect=0):
    p = subprocess.run([exe, "dataset", *map(str, args), "--quiet"], capture_output=True, text=True)
    assert p.returncode == expect, (args, p.returncode, p.stdout, p.stderr)
    return p


def files(folder):
    return sorted(p.relative_to(folder) for p in folder.rglob("*") if p.is_file())


def same_files(a, b, skip=("manifest.json",)):
    fa, fb = files(a), files(b)
    assert fa == fb, set(fa) ^ set(fb)
    for f in fa:
        if f.name in skip:
            continue
        assert filecmp.cmp(a / f, b / f, shallow=False), f"{f} differs"
    return len(fa)


def main():
    exe, scene, viewer, scratch = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3]), Path(sys.argv[4])
    shutil.rmtree(scratch, ignore_errors=True)
    spec = importlib.util.spec_from_file_location("coco_view", viewer)
    coco_view = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(coco_view)

    one, two = scratch / "t1", scratch / "t2"
    run(exe, scene, "--out", one, "--threads", 1)
    run(exe, scene, "--out", two, "--threads", 2)
    n = same_files(one, two)
    print(f"threads 1 and 2: {n} files identical")

    truth = json.loads((one / "truth.json").read_text())
    bunches = {b["bunch_uid"]: b for b in truth["bunches"]}
    split_of_seed = {}
    for b in truth["bunches"]:
        assert split_of_seed.setdefault(b["bunch_seed"], b["split"]) == b["split"], "a bunch seed in two splits"
    images_seen = set()
    totals = {}
    for split in ("train", "val", "test"):
        coco = json.loads((one / "annotations" / f"{split}.json").read_text())
        names = {c["id"]: c["name"] for c in coco["categories"]}
        assert names == {1: "bunch", 2: "berry", 3: "stalk", 4: "leaf", 5: "cane"}, names
        images = {im["id"]: im for im in coco["images"]}
        assert not images_seen & set(images), "an image in two splits"
        images_seen |= set(images)
        ids = [a["id"] for a in coco["annotations"]]
        assert len(ids) == len(set(ids)), "duplicate annotation ids"
        by_image = {}
        for a in coco["annotations"]:
            by_image.setdefault(a["image_id"], []).append(a)
        for iid, im in images.items():
            assert im["file_name"].startswith(f"images/{split}/"), im["file_name"]
            inst = cv2.imread(str(one / im["instance_file"]), cv2.IMREAD_UNCHANGED)
            sem = cv2.imread(str(one / im["semantic_file"]), cv2.IMREAD_UNCHANGED)
            depth = cv2.imread(str(one / im["depth_float_file"]), cv2.IMREAD_UNCHANGED)
            depth_mm = cv2.imread(str(one / im["depth_file"]), cv2.IMREAD_UNCHANGED)
            colour = cv2.imread(str(one / im["file_name"]), cv2.IMREAD_COLOR)
            assert inst.dtype == np.uint16 and depth_mm.dtype == np.uint16 and depth.dtype == np.float32
            assert colour.shape == (im["height"], im["width"], 3) and inst.shape == colour.shape[:2]
            assert np.all((depth > 0) == (sem > 0)), "depth where nothing is hit, or none where something is"
            assert np.abs(depth_mm.astype(float) - np.round(depth * 1000)).max() <= 1
            K = im["intrinsics"]
            pose = np.array(im["pose"]).reshape(4, 4)
            to_cam = np.linalg.inv(pose)
            yolo = (one / "labels" / split / (Path(im["file_name"]).stem + ".txt")).read_text().split("\n")
            anns = by_image.get(iid, [])
            assert len([y for y in yolo if y]) == len(anns)
            for a, line in zip(anns, yolo):
                name = names[a["category_id"]]
                totals[name] = totals.get(name, 0) + 1
                vis = coco_view.rle_decode(a["segmentation"])
                amo = coco_view.rle_decode(a["amodal_segmentation"])
                assert vis.sum() == a["area"] > 0 and amo.sum() == a["amodal_area"]
                assert not (vis & ~amo).any(), "visible pixels outside the amodal mask"
                assert abs(a["visible_fraction"] - a["area"] / a["amodal_area"]) < 1e-12
                ys, xs = np.nonzero(vis)
                assert a["bbox"] == [xs.min(), ys.min(), xs.max() - xs.min() + 1, ys.max() - ys.min() + 1], a["bbox"]
                mine = inst == a["instance_id"]
                if name == "bunch":  # the union of its parts: its own pixels, its berries' and its stalk's
                    assert (vis & mine).sum() == mine.sum() and np.all(sem[vis] >= 1) and np.all(sem[vis] <= 4)
                else:
                    assert np.array_equal(vis, mine), f"{name} {a['id']}: mask and instance image differ"
                if name in ("berry", "leaf"):
                    want = 1 if name == "berry" else 6
                    assert np.all(sem[vis] == want), name
                cls, cx, cy, w, h = line.split()
                assert int(cls) == a["category_id"] - 1
                x, y, bw, bh = a["bbox"]
                assert abs(float(cx) - (x + bw / 2) / im["width"]) < 1e-5 and abs(float(w) - bw / im["width"]) < 1e-5
                if name == "berry":  # its truth centre projects inside its amodal box
                    b = bunches[a["bunch_uid"]]["berries"][a["berry"]]
                    p = to_cam @ np.append(b["centre"], 1.0)
                    u = K["fx"] * p[0] / p[2] + K["cx"]
                    v = K["fy"] * p[1] / p[2] + K["cy"]
                    ax, ay, aw, ah = a["amodal_bbox"]
                    assert ax - 1 <= u <= ax + aw and ay - 1 <= v <= ay + ah, (u, v, a["amodal_bbox"])
                    r_px = K["fx"] * b["radius"] / p[2]
                    assert abs(a["amodal_area"] - np.pi * r_px * r_px) < 2 * np.pi * r_px + 4, (a["amodal_area"], r_px)
                if name in ("bunch", "stalk"):
                    assert split_of_seed[bunches[a["bunch_uid"]]["bunch_seed"]] == split
    print("annotations per category:", totals)
    for name in ("bunch", "berry", "stalk", "leaf", "cane"):
        assert totals.get(name, 0) > 0, f"no {name} annotated"
    assert sum(1 for b in truth["bunches"]) == 6  # 3 cases x 2 bunches

    # The viewer draws them.
    out = subprocess.run([sys.executable, str(viewer), str(one), "--images", "1", "--amodal", "--out",
                          str(scratch / "view")], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert cv2.imread(out.stdout.split()[0]) is not None

    # A folder with files: refused (exit 2, naming it); another scene: never mixed in.
    p = run(exe, scene, "--out", one, expect=2)
    assert str(one) in p.stderr and "--resume" in p.stderr, p.stderr
    other = scratch / "other.yaml"
    other.write_text(scene.read_text().replace("seed: 7", "seed: 8"))
    p = run(exe, other, "--out", one, "--resume", expect=2)
    assert "another scene" in p.stderr, p.stderr
    # No colour camera, or an output that is a file: exit 2 with the reason.
    depth = scratch / "depth.yaml"
    depth.write_text("name: depth\nseed: 1\nbunches: [{preset: summer-black}]\nsensor: {type: ideal}\n"
                     "rig: {type: stereo_stations, distances: [0.5]}\n")
    p = run(exe, depth, "--out", scratch / "depth_out", expect=2)
    assert "colour camera" in p.stderr, p.stderr
    p = run(exe, scene, "--out", other, expect=2)
    assert "not a folder" in p.stderr, p.stderr
    # Interrupted: a case's part and one of its images gone; resumed to the same files.
    parts = sorted((two / "parts").iterdir())
    parts[-1].unlink()
    next((two / "images").rglob("000002_001.png")).unlink()
    (two / "manifest.json").unlink()
    p = run(exe, scene, "--out", two, "--resume")
    same_files(one, two)
    print("refused, not mixed, resumed: ok")

    # A camera that stores JPEG: its own file, not a PNG of it, named by file_name.
    jpeg = scratch / "jpeg.yaml"
    text = scene.read_text().replace("count: 3", "count: 1").replace("  light: front\n",
                                                                       "  light: front\n  camera: {jpeg_quality: 90}\n")
    assert "jpeg_quality" in text
    jpeg.write_text(text)
    run(exe, jpeg, "--out", scratch / "jpeg_out")
    images = [im for split in ("train", "val", "test")
              for im in json.loads((scratch / "jpeg_out/annotations" / f"{split}.json").read_text())["images"]]
    assert images and all(im["file_name"].endswith(".jpg") for im in images), images[:1]
    for im in images:
        data = (scratch / "jpeg_out" / im["file_name"]).read_bytes()
        assert data[:2] == b"\xff\xd8", im["file_name"]
        assert cv2.imread(str(scratch / "jpeg_out" / im["file_name"])).shape == (im["height"], im["width"], 3)
    print(f"jpeg camera: {len(images)} .jpg images")
    return 0


if __name__ == "__main__":
    sys.exit(main())
