"""grapebench.scoring: the harness's scoring functions on hand cases with known answers."""
import math

import numpy as np
import pytest

import grapebench as gb
from grapebench import scoring


def test_scalars_count_failures_and_give_the_errors():
    s = scoring.scalars([1, 2, 3, np.nan], [1, 2, 4, 5])
    assert (s["cases"], s["succeeded"]) == (4, 3) and s["success_rate"] == pytest.approx(0.75)
    assert s["rmse"] == pytest.approx(math.sqrt(1 / 3)) and s["bias"] == pytest.approx(-1 / 3)
    assert s["mape"] == pytest.approx(25 / 3) and s["mae"] == pytest.approx(1 / 3)
    with pytest.raises(gb.InputError, match="one per case"):
        scoring.scalars([1, 2], [1, 2, 3])


def test_agreement_and_paired_comparison():
    assert scoring.concordance([1, 2, 3], [1, 2, 3]) == pytest.approx(1)
    ba = scoring.bland_altman([1, 2, 3], [0, 1, 2])
    assert ba == pytest.approx({"mean_difference": 1, "lower": 1, "upper": 1})
    c = scoring.compare_paired(np.zeros(20), np.ones(20), seed=3, resamples=200)
    assert c["cases"] == 20 and c["mean_difference"] == pytest.approx(-1) and c["p"] < 1e-4
    iv = scoring.bootstrap(np.arange(1, 21) * 1.1, np.arange(1, 21), seed=2, resamples=200)
    assert iv["bias"]["lo"] <= 1.05 <= iv["bias"]["hi"]
    with pytest.raises(gb.InputError, match="resamples"):
        scoring.bootstrap([1, 2, 3], [1, 2, 3], resamples=1)


def test_points_success_within_the_tolerance():
    s = scoring.points([[0, 0, 0], [1, 0, 0], [np.nan] * 3], np.zeros((3, 3)), 0.5)
    assert (s["cases"], s["answered"], s["within"]) == (3, 2, 1)
    assert s["success_rate"] == pytest.approx(1 / 3) and s["max_error"] == pytest.approx(1)
    assert s["axis_bias"] == pytest.approx([0.5, 0, 0])
    with pytest.raises(gb.InputError, match="N x 3"):
        scoring.points(np.zeros((2, 2)), np.zeros((2, 3)), 0.1)


def test_classes_perfect_scores():
    s = scoring.classes([0, 1, 1, 0], [[0.9, 0.1], [0.2, 0.8], [0.3, 0.7], [0.6, 0.4]], ["berry", "leaf"])
    assert s["accuracy"] == 1 and s["miou"] == 1 and s["auc"] == [1, 1]
    assert s["confusion"].tolist() == [[2, 0], [0, 2]]
    with pytest.raises(gb.InputError, match="outside"):
        scoring.classes([0, 2], [[1, 0], [0, 1]], ["a", "b"])


def test_detections_match_one_and_count_a_false_positive():
    s = scoring.detections([[10, 10, 5, 0.9], [50, 50, 5, 0.5]], [[10, 10, 5]])
    assert (s["matched"], s["false_positives"]) == (1, 1) and s["precision"] == 0.5 and s["recall"] == 1
    assert s["match"] == [0, -1]
    with pytest.raises(gb.InputError, match="rule"):
        scoring.detections([[1, 1, 1, 1]], [[1, 1, 1]], rule="nearest")


def test_coco_scores_the_truth_itself_one():
    gt = {"images": [{"id": 1, "width": 100, "height": 80}],
          "categories": [{"id": 1, "name": "bunch"}],
          "annotations": [{"id": 1, "image_id": 1, "category_id": 1, "bbox": [10, 10, 30, 20], "area": 600,
                           "iscrowd": 0}]}
    r = scoring.coco(gt, [{"image_id": 1, "category_id": 1, "bbox": [10, 10, 30, 20], "score": 0.9}])
    assert r["stats"]["AP"] == pytest.approx(1) and r["per_category"]["bunch"]["AP50"] == pytest.approx(1)
    with pytest.raises(gb.InputError):
        scoring.coco(gt, [{"image_id": 7, "category_id": 1, "bbox": [0, 0, 1, 1], "score": 1}])


def test_colour_difference_and_ssim():
    # Sharma, Wu and Dalal (2005), the CIEDE2000 test data's first pair.
    assert scoring.ciede2000([50, 2.6772, -79.7751], [50, 0, -82.7485]) == pytest.approx(2.0425, abs=1e-4)
    assert scoring.srgb8_to_lab([255, 255, 255]) == pytest.approx([100, 0, 0], abs=1e-3)
    img = np.random.default_rng(0).integers(0, 256, size=(40, 50, 3), dtype=np.uint8)
    assert scoring.luminance_ssim(img, img) == pytest.approx(1)
    with pytest.raises(gb.InputError, match="one size"):
        scoring.luminance_ssim(img, img[:20])
