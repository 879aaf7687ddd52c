// Detection scores: exact disc IoU values, and a hand-worked matching of four
// detections against three objects (one of them not visible).
#include "bench/scoring/detections.h"

#include <gtest/gtest.h>

#include <cmath>

namespace grapebench {
namespace {

TEST(DiscIou, ExactValues) {
  EXPECT_DOUBLE_EQ(disc_iou({0, 0, 3}, {0, 0, 3}), 1);
  EXPECT_DOUBLE_EQ(disc_iou({0, 0, 1}, {5, 0, 1}), 0);
  EXPECT_DOUBLE_EQ(disc_iou({0, 0, 1}, {0, 0, 2}), 0.25);  // nested: area ratio
  // Two unit discs one radius apart: lens 2 pi / 3 - sqrt(3) / 2.
  const double lens = 2 * M_PI / 3 - std::sqrt(3.0) / 2;
  EXPECT_NEAR(disc_iou({0, 0, 1}, {1, 0, 1}), lens / (2 * M_PI - lens), 1e-12);
  EXPECT_DOUBLE_EQ(disc_iou({0, 0, 0}, {0, 0, 1}), 0);
}

// Objects T0 (0, 0), T1 (100, 0) visible, T2 (200, 0) hidden, all r = 10. D0 (score
// 0.9) takes T0; D2 (0.8) takes the hidden T2 (no false positive, no recall); D3
// (0.7) is far from all; D1 (0.5) would fit T0 best, but D0 took it.
TEST(DetectionScores, GreedyByScoreAgainstVisibleAndHiddenObjects) {
  const std::vector<TruthObject> truth = {{{0, 0, 10}, true}, {{100, 0, 10}, true}, {{200, 0, 10}, false}};
  const std::vector<Detection> det = {{{1, 0, 10}, 0.9}, {{0, 0, 10}, 0.5}, {{200, 1, 11}, 0.8}, {{500, 0, 5}, 0.7}};
  for (const auto rule : {DetectionMatch::Rule::DiscIou, DetectionMatch::Rule::CentreInRadius}) {
    const DetectionScore s = score_detections(det, truth, {rule, 0.5});
    EXPECT_EQ(s.match, (std::vector<int>{0, -1, 2, -1}));
    EXPECT_EQ(s.matched, 2);
    EXPECT_EQ(s.false_positives, 2);
    EXPECT_EQ(s.visible, 2);
    EXPECT_EQ(s.visible_found, 1);
    EXPECT_DOUBLE_EQ(s.precision, 0.5);
    EXPECT_DOUBLE_EQ(s.recall, 0.5);
    EXPECT_DOUBLE_EQ(s.f1, 0.5);
    EXPECT_DOUBLE_EQ(s.centre_error_mean, 1);
    EXPECT_DOUBLE_EQ(s.radius_error_mean, 0.5);
    EXPECT_DOUBLE_EQ(s.radius_error_mae, 0.5);
  }
  // A stricter rule turns D2 (IoU 0.78 with T2) away too.
  EXPECT_EQ(score_detections(det, truth, {DetectionMatch::Rule::DiscIou, 0.9}).matched, 1);
  EXPECT_EQ(DetectionMatch{}.describe(), "disc IoU >= 0.5");
}

TEST(DetectionScores, PoolingSumsCountsAndWeightsErrors) {
  DetectionScore a, b;
  a.detections = 2, a.matched = 1, a.visible = 2, a.visible_found = 1, a.centre_error_mean = 2;
  a.radius_error_mean = 1, a.radius_error_mae = 1;
  b.detections = 4, b.matched = 3, b.visible = 3, b.visible_found = 3, b.centre_error_mean = 6;
  b.radius_error_mean = -1, b.radius_error_mae = 1;
  const DetectionScore p = pool_detection_scores({a, b});
  EXPECT_DOUBLE_EQ(p.precision, 4.0 / 6);
  EXPECT_DOUBLE_EQ(p.recall, 4.0 / 5);
  EXPECT_DOUBLE_EQ(p.centre_error_mean, (2 + 18) / 4.0);
  EXPECT_DOUBLE_EQ(p.radius_error_mean, (1 - 3) / 4.0);
  const DetectionScore empty = score_detections({}, {}, {});
  EXPECT_TRUE(std::isnan(empty.precision));
  EXPECT_TRUE(std::isnan(empty.f1));
}

}  // namespace
}  // namespace grapebench
