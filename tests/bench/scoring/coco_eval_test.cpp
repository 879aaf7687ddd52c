#include "bench/scoring/coco_eval.h"

#include <gtest/gtest.h>

#include "synth/config.h"

namespace grapebench {
namespace {

// One category, images of 200 x 200; boxes as {x, y, w, h}.
struct Case {
  CocoGroundTruth gt;
  std::vector<CocoObject> dets;
  explicit Case(int images = 1) {
    for (int i = 1; i <= images; ++i) gt.images.push_back({i, 200, 200});
    gt.categories.push_back({1, "berry"});
  }
  void truth(std::array<double, 4> b, bool crowd = false, std::int64_t image = 1) {
    CocoObject g;
    g.id = static_cast<std::int64_t>(gt.annotations.size()) + 1;
    g.image_id = image, g.category_id = 1, g.bbox = b, g.area = b[2] * b[3], g.iscrowd = crowd;
    gt.annotations.push_back(g);
  }
  void det(std::array<double, 4> b, double score, std::int64_t image = 1) {
    CocoObject d;
    d.id = static_cast<std::int64_t>(dets.size()) + 1;
    d.image_id = image, d.category_id = 1, d.bbox = b, d.area = b[2] * b[3], d.score = score;
    dets.push_back(d);
  }
  std::array<double, 12> stats() const { return coco_evaluate(gt, dets, {}).stats; }
};

enum { AP, AP50, AP75, APs, APm, APl, AR1, AR10, AR100 };

// The AR entries carry the limits in force: a raised limit is never called AR_100.
TEST(CocoEval, StatNamesFollowTheLimits) {
  EXPECT_EQ(coco_stat_name(0, {1, 10, 100}), "AP");
  EXPECT_EQ(coco_stat_name(8, {1, 10, 100}), "AR_100");
  EXPECT_EQ(coco_stat_name(6, {5, 20, 1000}), "AR_5");
  EXPECT_EQ(coco_stat_name(7, {5, 20, 1000}), "AR_20");
  EXPECT_EQ(coco_stat_name(8, {5, 20, 1000}), "AR_1000");
  EXPECT_EQ(coco_stat_name(9, {5, 20, 1000}), "AR_small");
  EXPECT_THROW(coco_stat_name(12, {1, 10, 100}), std::out_of_range);
}

TEST(CocoEval, PerfectDetectionsScoreOne) {
  Case c;
  c.truth({10, 10, 20, 20}), c.truth({50, 50, 40, 40});
  c.det({10, 10, 20, 20}, 0.9), c.det({50, 50, 40, 40}, 0.8);
  const auto s = c.stats();
  EXPECT_DOUBLE_EQ(s[AP], 1); EXPECT_DOUBLE_EQ(s[AP50], 1); EXPECT_DOUBLE_EQ(s[AR100], 1);
  EXPECT_DOUBLE_EQ(s[APs], 1); EXPECT_DOUBLE_EQ(s[APm], 1);
  EXPECT_DOUBLE_EQ(s[APl], -1);  // no large ground truth: undefined
}

TEST(CocoEval, AShiftedBoxCountsOnlyAtThresholdsBelowItsIou) {
  // 10 x 10 shifted by 2 px: IoU 80 / 120 = 0.667, a match at 0.50..0.65 (4 of 10).
  Case c;
  c.truth({0, 0, 10, 10});
  c.det({2, 0, 10, 10}, 1);
  const auto s = c.stats();
  EXPECT_DOUBLE_EQ(s[AP], 0.4); EXPECT_DOUBLE_EQ(s[AP50], 1); EXPECT_DOUBLE_EQ(s[AP75], 0);
  EXPECT_DOUBLE_EQ(s[AR100], 0.4);
}

TEST(CocoEval, ADuplicateRankedFirstCostsPrecisionWhereItFailsToMatch) {
  // The shifted box (IoU 0.667) scored above the exact one: at 0.50..0.65 it takes the
  // object and the exact one is a false positive after full recall (precision 1); at
  // 0.70..0.95 it is a false positive before the exact one (precision 1/2 throughout).
  Case c;
  c.truth({0, 0, 10, 10});
  c.det({2, 0, 10, 10}, 0.9), c.det({0, 0, 10, 10}, 0.8);
  EXPECT_DOUBLE_EQ(c.stats()[AP], (4 * 1.0 + 6 * 0.5) / 10);
}

TEST(CocoEval, AMissedObjectHalvesRecallAndApReadsPrecisionAt51Of101Points) {
  Case c;
  c.truth({0, 0, 10, 10}), c.truth({50, 50, 10, 10});
  c.det({0, 0, 10, 10}, 1);
  const auto s = c.stats();
  EXPECT_DOUBLE_EQ(s[AR100], 0.5);
  EXPECT_NEAR(s[AP], 51.0 / 101, 1e-15);
}

TEST(CocoEval, AreaRangesScoreEachSizeAlone) {
  // 10 x 10 (small) found, 100 x 100 (large) missed.
  Case c;
  c.truth({0, 0, 10, 10}), c.truth({90, 90, 100, 100});
  c.det({0, 0, 10, 10}, 1);
  const auto s = c.stats();
  EXPECT_DOUBLE_EQ(s[APs], 1); EXPECT_DOUBLE_EQ(s[APl], 0); EXPECT_DOUBLE_EQ(s[APm], -1);
  // A large false positive is ignored in the small range (unmatched, outside it).
  c.det({100, 0, 100, 100}, 2);
  EXPECT_DOUBLE_EQ(c.stats()[APs], 1);
  EXPECT_NEAR(c.stats()[AP], 51.0 / 101 * 0.5, 1e-15);  // rank 2 at recall 0.5: precision 1/2
}

TEST(CocoEval, ACrowdRegionAbsorbsDetectionsInsteadOfCountingThemFalse) {
  Case c;
  c.truth({0, 0, 10, 10});
  c.truth({100, 100, 60, 60}, true);
  c.det({0, 0, 10, 10}, 0.5);
  c.det({100, 100, 20, 20}, 0.9), c.det({130, 130, 20, 20}, 0.8);  // inside the crowd: IoU over their own area, 1
  EXPECT_DOUBLE_EQ(c.stats()[AP], 1);
  Case plain;  // the same without the crowd flag: the crowd is one object, the second box a false positive
  plain.truth({0, 0, 10, 10});
  plain.truth({100, 100, 60, 60});
  plain.det({0, 0, 10, 10}, 0.5);
  plain.det({100, 100, 20, 20}, 0.9), plain.det({130, 130, 20, 20}, 0.8);
  EXPECT_LT(plain.stats()[AP], 0.5);
}

TEST(CocoEval, TheMaxDetectionsLimitCutsEachImagesLowestScores) {
  Case c;
  for (int k = 0; k < 3; ++k) c.truth({20.0 * k, 0, 10, 10}), c.det({20.0 * k, 0, 10, 10}, 1 - 0.1 * k);
  const auto s = c.stats();
  EXPECT_DOUBLE_EQ(s[AR1], 1.0 / 3); EXPECT_DOUBLE_EQ(s[AR10], 1); EXPECT_DOUBLE_EQ(s[AR100], 1);
  EXPECT_NEAR(coco_evaluate(c.gt, c.dets, {CocoIouType::Bbox, {1, 2, 2}}).stats[AR100], 2.0 / 3, 1e-15);
}

TEST(CocoEval, MasksAreComparedByTheirPixels) {
  Case c;
  std::vector<std::uint8_t> m(200 * 200, 0), half(200 * 200, 0);
  for (int v = 10; v < 30; ++v)
    for (int u = 10; u < 30; ++u) m[static_cast<std::size_t>(v * 200 + u)] = 1, half[static_cast<std::size_t>(v * 200 + u)] = u < 20;
  c.truth({10, 10, 20, 20});
  c.gt.annotations[0].mask = rle_encode(m.data(), 200, 200);
  c.det({10, 10, 20, 20}, 1);  // the right box, half the mask: IoU 0.5 in pixels
  c.dets[0].mask = rle_encode(half.data(), 200, 200);
  EXPECT_DOUBLE_EQ(coco_evaluate(c.gt, c.dets, {CocoIouType::Bbox, {1, 10, 100}}).stats[AP], 1);
  const auto s = coco_evaluate(c.gt, c.dets, {CocoIouType::Segm, {1, 10, 100}}).stats;
  EXPECT_DOUBLE_EQ(s[AP50], 1); EXPECT_DOUBLE_EQ(s[AP], 0.1);
}

// Bad results name the file, the record and what is allowed.
TEST(CocoEval, BadResultsAreRefusedNamingTheRecord) {
  Case c;
  c.truth({0, 0, 10, 10});
  auto refused = [&](const std::string& json, const std::string& want) {
    try {
      read_coco_results(nlohmann::json::parse(json), "r.json", c.gt, CocoIouType::Bbox);
      ADD_FAILURE() << json;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("r.json"), std::string::npos) << e.what();
    }
  };
  refused(R"([{"image_id": 9, "category_id": 1, "score": 1, "bbox": [0, 0, 1, 1]}])", "record 0: image_id 9");
  refused(R"([{"image_id": 1, "category_id": 1, "score": 1, "bbox": [0, 0, 1, 1]},
             {"image_id": 1, "category_id": 7, "score": 1, "bbox": [0, 0, 1, 1]}])", "record 1: category_id 7");
  refused(R"([{"image_id": 1, "category_id": 1, "score": 1, "bbox": [0, 0, -1, 1]}])", "negative width");
  refused(R"([{"image_id": 1, "category_id": 1, "score": 1, "bbox": [0, 0, 1]}])", "[x, y, w, h]");
  refused(R"([{"image_id": 1, "category_id": 1, "score": "high", "bbox": [0, 0, 1, 1]}])", "`score` must be a number");
  refused(R"([{"id": 3, "image_id": 1, "category_id": 1, "score": 1, "bbox": [0, 0, 1, 1]},
             {"id": 3, "image_id": 1, "category_id": 1, "score": 1, "bbox": [0, 0, 1, 1]}])", "duplicate id 3");
  refused(R"({"image_id": 1})", "a list of");
  // (NaN cannot be written in JSON and the parser refuses 1e999: `coco-eval` says "not JSON", exit 2.)
  try {
    read_coco_results(nlohmann::json::parse(R"([{"image_id": 1, "category_id": 1, "score": 1,
                                                 "segmentation": {"size": [100, 200], "counts": "0"}}])"),
                      "r.json", c.gt, CocoIouType::Segm);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mask of 100 x 200 (h x w) on image 1 of 200 x 200"), std::string::npos)
        << e.what();
  }
}

// Resampling: an image listed twice in coco_accumulate scores as a copy of it would
// (a new image with the same objects), so bootstrap resamples are COCO evaluations.
TEST(CocoEval, AccumulatingAnImageTwiceEqualsEvaluatingItsCopy) {
  Case c(2);
  c.truth({10, 10, 20, 20}, false, 1), c.truth({50, 50, 40, 40}, false, 1), c.truth({100, 100, 30, 30}, false, 2);
  c.det({10, 10, 20, 20}, 0.9, 1), c.det({52, 50, 40, 40}, 0.4, 1), c.det({0, 0, 10, 10}, 0.7, 2);
  c.det({100, 104, 30, 30}, 0.6, 2);
  const CocoEvaluation e = coco_evaluate_images(c.gt, c.dets, {});
  const CocoEvalResult twice = coco_accumulate(e, {0, 0, 1}, true);
  Case copy(3);  // images 1 and 2: image 1's objects; image 3: image 2's
  for (const std::int64_t im : {1, 2}) copy.truth({10, 10, 20, 20}, false, im), copy.truth({50, 50, 40, 40}, false, im);
  copy.truth({100, 100, 30, 30}, false, 3);
  for (const std::int64_t im : {1, 2}) copy.det({10, 10, 20, 20}, 0.9, im), copy.det({52, 50, 40, 40}, 0.4, im);
  copy.det({0, 0, 10, 10}, 0.7, 3), copy.det({100, 104, 30, 30}, 0.6, 3);
  const auto expect = copy.stats();
  for (std::size_t k = 0; k < 12; ++k) EXPECT_DOUBLE_EQ(twice.stats[k], expect[k]) << kCocoStatNames[k];
  // And the plain evaluation is the accumulation over every image once.
  const auto all = coco_accumulate(e, {0, 1}, true).stats, direct = c.stats();
  for (std::size_t k = 0; k < 12; ++k) EXPECT_DOUBLE_EQ(all[k], direct[k]) << kCocoStatNames[k];
}

TEST(CocoEval, BootstrapIntervalsHoldThePointEstimateAndCollapseWhenEveryImageIsPerfect) {
  Case perfect(6), mixed(6);
  for (std::int64_t im = 1; im <= 6; ++im) {
    perfect.truth({10, 10, 20, 20}, false, im), perfect.det({10, 10, 20, 20}, 0.9, im);
    mixed.truth({10, 10, 20, 20}, false, im);
    mixed.det(im % 2 ? std::array<double, 4>{10, 10, 20, 20} : std::array<double, 4>{100, 100, 20, 20}, 0.1 * im, im);
  }
  const CocoIntervals p = coco_bootstrap(coco_evaluate_images(perfect.gt, perfect.dets, {}), 7, 200);
  EXPECT_DOUBLE_EQ(p.ap.lo, 1); EXPECT_DOUBLE_EQ(p.ap.hi, 1);
  const CocoEvaluation me = coco_evaluate_images(mixed.gt, mixed.dets, {});
  const double ap = coco_accumulate(me, {0, 1, 2, 3, 4, 5}, true).stats[0];
  const CocoIntervals m = coco_bootstrap(me, 7, 400);
  EXPECT_LT(m.ap.lo, ap); EXPECT_GT(m.ap.hi, ap);
  EXPECT_GE(m.ap.lo, 0); EXPECT_LE(m.ap.hi, 1);
  // Resampling groups: one group of every image draws the same set each time, so the
  // interval collapses to the estimate; pairs of images give an interval of its own.
  const CocoIntervals whole = coco_bootstrap(me, 7, 100, 0.95, {{0, 1, 2, 3, 4, 5}});
  EXPECT_DOUBLE_EQ(whole.ap.lo, ap); EXPECT_DOUBLE_EQ(whole.ap.hi, ap);
  const CocoIntervals pairs = coco_bootstrap(me, 7, 400, 0.95, {{0, 1}, {2, 3}, {4, 5}});
  EXPECT_LE(pairs.ap.lo, ap); EXPECT_GE(pairs.ap.hi, ap);
  // Paired: the perfect detector against the mixed one, on the same resamples: AP
  // difference > 0 in every resample that is not all-perfect.
  const CocoIntervals d = coco_bootstrap_difference(coco_evaluate_images(perfect.gt, perfect.dets, {}), me, 7, 400);
  EXPECT_GE(d.ap.lo, 0); EXPECT_GT(d.ap.hi, 0);
}

}  // namespace
}  // namespace grapebench
