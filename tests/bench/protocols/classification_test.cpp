// The classification protocol's stages (seed 004): the row split leaves a gap and
// labels only the training part; the rows rate class scores on the test part alone,
// against values computed by hand.
#include <gtest/gtest.h>

#include "bench/classification_tables.h"
#include "bench/protocols/classification.h"

namespace grapebench {
namespace {

TEST(Classification, SplitLabelsTheTrainingPartAndDropsTheGap) {
  FusedCloud c;
  const double xs[] = {-0.5, -0.1, 0.0, 0.12, 0.4};
  const Part parts[] = {Part::Berry, Part::Leaf, Part::Cane, Part::Rachis, Part::Background};
  for (int i = 0; i < 5; ++i) {
    c.points.emplace_back(xs[i], 0, 0);
    c.colours.push_back({0, 0, 0});
    c.labels.push_back(parts[i]);
    c.depth_sd.push_back(0);
  }
  std::vector<int> truth;
  const std::vector<int> train = split_row(c, 0.2, truth);
  // -0.5 berry (train), -0.1 and 0.0 in the gap, 0.12 rachis (test), 0.4 background (no class).
  EXPECT_EQ(train, (std::vector<int>{0, -1}));
  EXPECT_EQ(truth, (std::vector<int>{0, 1}));
  ASSERT_EQ(c.points.size(), 2u);
  EXPECT_EQ(c.points[1].x(), 0.12);
  EXPECT_EQ(plant_class(Part::Pedicel), 1);
  EXPECT_EQ(plant_class(Part::Leaf), 2);
}

double row(const std::vector<EstimateRow>& rows, const std::string& q) {
  for (const auto& r : rows) {
    if (r.quantity == q) return r.ok ? r.estimate : NAN;
  }
  return -1;
}

TEST(Classification, RowsRateTheTestPartOnly) {
  // Five test points (truth berry, berry, branch, leaf, leaf) and one training point
  // whose scores must not count.
  const std::vector<int> train{-1, -1, -1, -1, -1, 2};
  const std::vector<int> truth{0, 0, 1, 2, 2, 2};
  Estimate e;
  e.class_scores.resize(6, 3);
  e.class_scores << 0.9, 0.05, 0.05,  // berry, right
      0.3, 0.6, 0.1,                  // berry taken for branch
      0.2, 0.7, 0.1,                  // branch, right
      0.6, 0.1, 0.3,                  // leaf taken for berry
      0.1, 0.1, 0.8,                  // leaf, right
      0.9, 0.0, 0.1;                  // training point: ignored
  EstimateRow base;
  base.estimator = "e";
  std::vector<ConfusionCounts> confusion;
  const std::vector<EstimateRow> rows = classification_rows(base, e, train, truth, nullptr, &confusion);
  ASSERT_EQ(confusion.size(), 1u);
  // Rows true berry, branch, leaf; columns predicted.
  EXPECT_EQ(confusion[0].counts, (std::vector<long long>{1, 1, 0, 0, 1, 0, 1, 0, 1}));
  EXPECT_DOUBLE_EQ(row(rows, "accuracy"), 3.0 / 5);
  EXPECT_DOUBLE_EQ(row(rows, "berry_tpr"), 0.5);        // 1 of 2 berries
  EXPECT_DOUBLE_EQ(row(rows, "berry_fpr"), 1.0 / 3);    // 1 of 3 others called berry
  EXPECT_DOUBLE_EQ(row(rows, "precision_berry"), 0.5);  // 1 of 2 called berry
  EXPECT_DOUBLE_EQ(row(rows, "iou_berry"), 1.0 / 3);    // 1 / (2 + 2 - 1)
  // Berry scores 0.9, 0.3 (positives) vs 0.2, 0.6, 0.1: 0.9 beats 3, 0.3 beats 2 of 3.
  EXPECT_DOUBLE_EQ(row(rows, "auc_berry"), 5.0 / 6);
  EXPECT_DOUBLE_EQ(row(rows, "miou"), (1.0 / 3 + 1.0 / 2 + 1.0 / 2) / 3);
  // A wrongly shaped answer fails every row, naming the shape.
  Estimate bad;
  bad.class_scores.resize(2, 3);
  const std::vector<EstimateRow> failed = classification_rows(base, bad, train, truth);
  ASSERT_FALSE(failed.empty());
  for (const auto& r : failed) {
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("2 x 3"), std::string::npos);
  }
}

TEST(Classification, ConfusionPooledOverCases) {
  // Two cases of one condition: the sums, and accuracy and mIoU of the summed matrix.
  CaseResult a, b, other;
  a.confusion.push_back({"e", {"x", "y"}, {3, 1, 0, 4}});
  b.confusion.push_back({"e", {"x", "y"}, {1, 0, 2, 1}});
  other.condition = 1;
  other.confusion.push_back({"e", {"x", "y"}, {100, 0, 0, 0}});
  const std::vector<PooledConfusion> p = pooled_confusion({a, b, other}, 0);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].counts, (std::vector<long long>{4, 1, 2, 5}));
  EXPECT_DOUBLE_EQ(p[0].accuracy, 9.0 / 12);
  // IoU x = 4 / (5 + 6 - 4) = 4/7; IoU y = 5 / (7 + 6 - 5) = 5/8.
  EXPECT_DOUBLE_EQ(p[0].miou, (4.0 / 7 + 5.0 / 8) / 2);
}

}  // namespace
}  // namespace grapebench
