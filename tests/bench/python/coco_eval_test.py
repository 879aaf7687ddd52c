"""`grapebench coco-eval` against a second implementation of COCO's rules written here
for the test (pycocotools is not packaged in Debian 12): random ground truth (crowd
regions, every area range, empty images) and detections (duplicates, ties in score,
more than the max-detections limit per image), boxes and masks; all 12 numbers overall
and per category agree to 1e-12. Then a dataset's own annotations as detections score 1.

usage: coco_eval_test.py <grapebench> <scratch folder> [<dataset folder>]
"""
import importlib.util
import json
import random
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

# The dataset viewer's RLE reader (its own test: tests/bench/python/dataset_test.py).
_spec = importlib.util.spec_from_file_location("coco_view", Path(__file__).resolve().parents[3] / "scripts" / "coco_view.py")
coco_view = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(coco_view)

AREAS = [(0, 1e10), (0, 32 ** 2), (32 ** 2, 96 ** 2), (96 ** 2, 1e10)]


def iou_boxes(d, g, crowd):
    """len(d) x len(g) IoU of [x, y, w, h] boxes; over the detection's area for crowds."""
    if len(d) == 0 or len(g) == 0:
        return np.zeros((len(d), len(g)))
    d, g = np.asarray(d, float), np.asarray(g, float)
    w = np.minimum(d[:, None, 0] + d[:, None, 2], g[None, :, 0] + g[None, :, 2]) - np.maximum(d[:, None, 0], g[None, :, 0])
    h = np.minimum(d[:, None, 1] + d[:, None, 3], g[None, :, 1] + g[None, :, 3]) - np.maximum(d[:, None, 1], g[None, :, 1])
    inter = np.where((w > 0) & (h > 0), w * h, 0.0)
    da, ga = d[:, 2] * d[:, 3], g[:, 2] * g[:, 3]
    union = np.where(np.asarray(crowd)[None, :], da[:, None], da[:, None] + ga[None, :] - inter)
    return np.where(union > 0, inter / np.where(union > 0, union, 1), 0.0)


def iou_masks(d, g, crowd):
    out = np.zeros((len(d), len(g)))
    for i, a in enumerate(d):
        for j, b in enumerate(g):
            inter = np.logical_and(a, b).sum()
            union = a.sum() if crowd[j] else np.logical_or(a, b).sum()
            out[i, j] = inter / union if union else 0.0
    return out


def evaluate(gt, dets, kind, max_dets=(1, 10, 100)):
    """The 12 numbers, overall and per category id."""
    iou_thrs = np.linspace(0.5, 0.95, 10)
    rec_thrs = np.linspace(0.0, 1.0, 101)
    images = sorted(im["id"] for im in gt["images"])
    cats = sorted(c["id"] for c in gt["categories"])
    T, R, K, A, M = len(iou_thrs), len(rec_thrs), len(cats), len(AREAS), len(max_dets)
    precision = -np.ones((T, R, K, A, M))
    recall = -np.ones((T, K, A, M))

    def mask_of(o):
        return coco_view.rle_decode(o["segmentation"])

    for k, cat in enumerate(cats):
        per_image = []
        for img in images:
            g = [a for a in gt["annotations"] if a["image_id"] == img and a["category_id"] == cat]
            d = [r for r in dets if r["image_id"] == img and r["category_id"] == cat]
            if not g and not d:
                continue
            order = sorted(range(len(d)), key=lambda i: -d[i]["score"])  # Python's sort is stable
            d = [d[i] for i in order][:max_dets[-1]]
            crowd = [bool(a.get("iscrowd", 0)) for a in g]
            if kind == "bbox":
                ious = iou_boxes([x["bbox"] for x in d], [a["bbox"] for a in g], crowd)
            else:
                ious = iou_masks([mask_of(x) for x in d], [mask_of(a) for a in g], crowd)
            d_area = [x["bbox"][2] * x["bbox"][3] if kind == "bbox" else mask_of(x).sum() for x in d]
            per_image.append((g, d, ious, crowd, d_area))
        for ai, (lo, hi) in enumerate(AREAS):
            rows = []  # per image: scores, matched[T, D], ignored[T, D], number of counted ground truths
            for g, d, ious, crowd, d_area in per_image:
                g_ign = np.array([crowd[j] or not lo <= g[j]["area"] <= hi for j in range(len(g))], bool)
                gorder = np.argsort(g_ign, kind="stable")
                matched = np.zeros((T, len(d)), bool)
                ignored = np.zeros((T, len(d)), bool)
                for t, thr in enumerate(iou_thrs):
                    taken = np.zeros(len(g), bool)
                    for i in range(len(d)):
                        best, m = min(thr, 1 - 1e-10), -1
                        for j in gorder:
                            if taken[j] and not crowd[j]:
                                continue
                            if m > -1 and not g_ign[m] and g_ign[j]:
                                break
                            if ious[i, j] < best:
                                continue
                            best, m = ious[i, j], j
                        if m > -1:
                            matched[t, i], ignored[t, i], taken[m] = True, g_ign[m], True
                outside = np.array([not lo <= a <= hi for a in d_area], bool)
                ignored |= ~matched & outside[None, :]
                rows.append((np.array([x["score"] for x in d]), matched, ignored, int((~g_ign).sum())))
            for mi, cut in enumerate(max_dets):
                npig = sum(r[3] for r in rows)
                if npig == 0:
                    continue
                scores = np.concatenate([r[0][:cut] for r in rows]) if rows else np.zeros(0)
                order = np.argsort(-scores, kind="stable")
                mt = np.concatenate([r[1][:, :cut] for r in rows], axis=1)[:, order]
                ig = np.concatenate([r[2][:, :cut] for r in rows], axis=1)[:, order]
                tp = np.cumsum(mt & ~ig, axis=1).astype(float)
                fp = np.cumsum(~mt & ~ig, axis=1).astype(float)
                for t in range(T):
                    nd = tp.shape[1]
                    rc = tp[t] / npig
                    pr = tp[t] / (fp[t] + tp[t] + np.spacing(1))
                    recall[t, k, ai, mi] = rc[-1] if nd else 0
                    pr = np.maximum.accumulate(pr[::-1])[::-1] if nd else pr
                    at = np.searchsorted(rc, rec_thrs, side="left")
                    precision[t, :, k, ai, mi] = np.where(at < nd, pr[np.minimum(at, max(nd - 1, 0))] if nd else 0, 0)

    def stats(ks):
        def mean(x):
            x = x[x > -1]
            return float(x.mean()) if x.size else -1.0
        p, r, last = precision[:, :, ks], recall[:, ks], M - 1
        ap = lambda t, a: mean(p[t if t is not None else slice(None), :, :, a, last])
        return [ap(None, 0), ap(0, 0), ap(5, 0), ap(None, 1), ap(None, 2), ap(None, 3),
                mean(r[:, :, 0, 0]), mean(r[:, :, 0, 1]), mean(r[:, :, 0, 2]),
                mean(r[:, :, 1, last]), mean(r[:, :, 2, last]), mean(r[:, :, 3, last])]

    return stats(list(range(K))), {cat: stats([k]) for k, cat in enumerate(cats)}


NAMES = ["AP", "AP50", "AP75", "AP_small", "AP_medium", "AP_large", "AR_1", "AR_10", "AR_100", "AR_small",
         "AR_medium", "AR_large"]


def random_case(rng, kind):
    W, H = 320, 240
    gt = {"images": [{"id": i, "width": W, "height": H} for i in (3, 1, 2, 7)],
          "categories": [{"id": 2, "name": "berry"}, {"id": 1, "name": "bunch"}], "annotations": []}
    dets = []

    def box():
        s = rng.choice([6, 20, 45, 120])
        w, h = rng.uniform(0.5, 1.5) * s, rng.uniform(0.5, 1.5) * s
        return [round(rng.uniform(0, W - w)), round(rng.uniform(0, H - h)), round(w), round(h)]

    def mask(b):
        m = np.zeros((H, W), bool)
        x, y, w, h = b
        m[y:y + h, x:x + w] = True
        if w > 4 and h > 4:
            m[y + h // 2:, x:x + w // 3] = False  # not a rectangle: masks differ from boxes
        return m

    for im in (3, 1, 2):  # image 7 stays empty
        for _ in range(rng.randint(0, 14)):
            b = box()
            m = mask(b)
            a = {"id": len(gt["annotations"]) + 1, "image_id": im, "category_id": rng.choice([1, 2]), "bbox": b,
                 "area": int(m.sum()), "iscrowd": int(rng.random() < 0.1), "segmentation": {"size": [H, W], "counts": coco_view.rle_string(m)}}
            gt["annotations"].append(a)
            for _ in range(rng.choice([0, 1, 1, 2])):  # missed, found, duplicated
                j = [v + rng.choice([0, 0, 1, -2, 4]) for v in b]
                j[2], j[3] = max(j[2], 1), max(j[3], 1)
                j[0], j[1] = min(max(j[0], 0), W - j[2]), min(max(j[1], 0), H - j[3])
                dets.append({"image_id": im, "category_id": a["category_id"], "score": rng.choice([0.3, 0.5, 0.5, 0.9, rng.random()]),
                             "bbox": j, "segmentation": {"size": [H, W], "counts": coco_view.rle_string(mask(j))}})
        for _ in range(rng.randint(0, 6)):  # false positives
            b = box()
            dets.append({"image_id": im, "category_id": rng.choice([1, 2]), "score": rng.random(), "bbox": b,
                         "segmentation": {"size": [H, W], "counts": coco_view.rle_string(mask(b))}})
    if kind == "bbox":
        for d in dets:
            del d["segmentation"]
    return gt, dets


def run(exe, gt_path, res_path, kind, out, max_dets=None):
    cmd = [exe, "coco-eval", str(gt_path), str(res_path), "--iou", kind, "--json", str(out)]
    if max_dets:
        cmd += ["--max-dets", *map(str, max_dets)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return json.loads(out.read_text())


def main():
    exe, scratch = sys.argv[1], Path(sys.argv[2])
    shutil.rmtree(scratch, ignore_errors=True)
    scratch.mkdir(parents=True)
    rng = random.Random(42)
    worst = 0.0
    for trial in range(16):
        kind = "bbox" if trial % 2 == 0 else "segm"
        gt, dets = random_case(rng, kind)
        max_dets = (1, 3, 5) if trial % 3 == 0 else (1, 10, 100)  # a low limit the random images exceed
        (scratch / "gt.json").write_text(json.dumps(gt))
        (scratch / "res.json").write_text(json.dumps(dets))
        mine = run(exe, scratch / "gt.json", scratch / "res.json", kind, scratch / "out.json", max_dets)
        ref_all, ref_cat = evaluate(gt, dets, kind, max_dets)
        names = {c["id"]: c["name"] for c in gt["categories"]}
        # The AR entries are named after the limits in force (AR_3, AR_5 at (1, 3, 5)).
        for i, n in enumerate(NAMES[:6] + [f"AR_{m}" for m in max_dets] + NAMES[9:]):
            worst = max(worst, abs(mine["all"][n] - ref_all[i]))
            assert abs(mine["all"][n] - ref_all[i]) < 1e-12, (trial, kind, n, mine["all"][n], ref_all[i])
            for cid, s in ref_cat.items():
                assert abs(mine["categories"][names[cid]][n] - s[i]) < 1e-12, (trial, names[cid], n)
    print(f"16 random cases (boxes and masks): every number within {worst:.1e} of the second implementation")

    if len(sys.argv) > 3:  # a dataset's own annotations, as detections, score 1 where there is any
        dataset = Path(sys.argv[3])
        for split in ("train", "test", "val"):
            gt_path = dataset / "annotations" / f"{split}.json"
            gt = json.loads(gt_path.read_text())
            if gt["annotations"]:
                break
        dets = [{"image_id": a["image_id"], "category_id": a["category_id"], "score": 1.0, "bbox": a["bbox"],
                 "segmentation": a["segmentation"]} for a in gt["annotations"]]
        (scratch / "self.json").write_text(json.dumps(dets))
        for kind in ("bbox", "segm"):
            s = run(exe, gt_path, scratch / "self.json", kind, scratch / "self_out.json", (1, 10, 10000))
            assert s["all"]["AP"] == 1.0 and s["all"]["AR_10000"] == 1.0, s["all"]
        print(f"{split}: its own {len(dets)} annotations score AP 1 (boxes and masks)")
        # The external baseline (scripts/baseline_detector.py) reads the images alone and
        # writes results coco-eval accepts: berries and bunches, masks of the image's size.
        baseline = Path(__file__).resolve().parents[3] / "scripts" / "baseline_detector.py"
        p = subprocess.run([sys.executable, str(baseline), str(dataset), "--split", split, "--out",
                            str(scratch / "base.json")], capture_output=True, text=True)
        assert p.returncode == 0, p.stderr
        base = json.loads((scratch / "base.json").read_text())
        assert {r["category_id"] for r in base} <= {1, 2} and base, "no detections"
        s = run(exe, gt_path, scratch / "base.json", "segm", scratch / "base_out.json")
        assert all(-1 <= v <= 1 for v in s["all"].values()), s
        print(f"baseline: {len(base)} detections scored, AP {s['all']['AP']:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
