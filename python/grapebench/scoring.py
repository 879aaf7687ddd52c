"""The harness's scoring functions (bench/scoring/) on numpy input, the ones behind
results.csv and summary.json, so a notebook scores its own estimates exactly as a run
does. Each returns a dict (or a number); bad input raises grapebench.InputError."""
import json

import numpy as np

from . import _grapebench


def scalars(estimate, truth):
    """R2 (squared Pearson), R2 about the identity line, RMSE, MAE, bias, MAPE (percent),
    slope and intercept of estimate against truth, one value per case in your units; a
    non-finite estimate is a failed case (counted in `cases`, not in the statistics)."""
    return _grapebench.score_scalars(_vector(estimate), _vector(truth))


def bootstrap(estimate, truth, seed=1, resamples=2000, level=0.95):
    """BCa bootstrap intervals of RMSE, bias, MAPE and R2 ({lo, hi} each), drawn from seed."""
    return _grapebench.bootstrap_scalars(_vector(estimate), _vector(truth), int(seed), int(resamples), float(level))


def concordance(estimate, truth):
    """Lin's concordance correlation coefficient (1 only when estimate = truth)."""
    return _grapebench.concordance(_vector(estimate), _vector(truth))


def bland_altman(estimate, truth):
    """Mean difference estimate - truth and the 95 % limits of agreement."""
    return _grapebench.bland_altman(_vector(estimate), _vector(truth))


def compare_paired(abs_error_a, abs_error_b, seed=1, resamples=2000, level=0.95):
    """Two estimators on the same cases: mean of |error A| - |error B| (negative: A closer),
    its bootstrap interval and the Wilcoxon signed-rank p."""
    return _grapebench.compare_paired(_vector(abs_error_a), _vector(abs_error_b), int(seed), int(resamples),
                                      float(level))


def points(estimate, truth, tolerance):
    """3D points (N x 3, m; a non-finite row did not answer) against the exact ones:
    success rate within `tolerance` (m), Euclidean and per-axis errors (seed 001's
    cutting point)."""
    return _grapebench.score_points(_rows(estimate, 3), _rows(truth, 3), float(tolerance))


def classes(truth, scores, names):
    """Per-point classification: truth (N class indices), scores (N x K, higher = more
    likely), names (K). Confusion matrix, per-class precision / recall / IoU, accuracy,
    mIoU, and per class the one-vs-rest ROC curve and AUC (seed 004)."""
    return _grapebench.score_classes([int(t) for t in np.asarray(truth).ravel()],
                                     np.asarray(scores, dtype=np.float64), list(names))


def detections(found, truth, visible=None, rule="disc_iou", threshold=0.5):
    """Circles in an image (seed 001's berries): found (M x 4: x, y, r, score; px), truth
    (K x 3: x, y, r), visible (K flags, counted for recall; default all). rule: disc_iou
    or centre_in_radius. Precision, recall, F1, errors and each detection's match."""
    truth = _rows(truth, 3)
    visible = [True] * len(truth) if visible is None else [bool(v) for v in visible]
    return _grapebench.score_detections(_rows(found, 4), truth, visible, rule, float(threshold))


def coco(ground_truth, results, iou_type="bbox", max_dets=(1, 10, 100)):
    """COCO's 12 summary numbers (COCOeval.summarize) overall and per category, as
    `grapebench coco-eval`: ground_truth a COCO dataset (dict, or a path to its JSON),
    results a list of COCO result records (or a path)."""
    return _grapebench.coco_evaluate(_json_text(ground_truth), _json_text(results), iou_type,
                                     [int(d) for d in max_dets])


def ciede2000(lab1, lab2):
    """CIEDE2000 colour difference of two CIELAB colours."""
    return _grapebench.ciede2000(np.asarray(lab1, dtype=np.float64), np.asarray(lab2, dtype=np.float64))


def srgb8_to_lab(rgb):
    """CIELAB (D65) of an 8-bit sRGB colour."""
    r, g, b = (int(v) for v in rgb)
    return _grapebench.srgb8_to_lab(r, g, b)


def luminance_ssim(a, b):
    """Mean SSIM of the Rec. 709 luma of two H x W x 3 uint8 images (Wang et al. 2004)."""
    return _grapebench.luminance_ssim(np.asarray(a), np.asarray(b))


def _vector(x):
    return [float(v) for v in np.asarray(x, dtype=np.float64).ravel()]


def _rows(x, cols):
    a = np.asarray(x, dtype=np.float64)
    if a.size == 0:
        a = a.reshape(0, cols)
    if a.ndim != 2 or a.shape[1] != cols:
        raise _grapebench.InputError("expected an N x %d array, got shape %s" % (cols, a.shape))
    return a


def _json_text(x):
    if isinstance(x, (dict, list)):
        return json.dumps(x)
    with open(x) as f:
        return f.read()
