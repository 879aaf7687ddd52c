// Classification scores on a hand-worked case of six points and three classes: one
// right per class, one wrong per class (one by a tie, broken to the lowest index).
#include "bench/scoring/classes.h"

#include <gtest/gtest.h>

#include <cmath>

namespace grapebench {
namespace {

ClassScores hand_case() {
  Eigen::MatrixXd scores(6, 3);
  scores << 0.9, 0.1, 0.0,  // truth 0, predicted 0
      0.2, 0.7, 0.1,        // truth 0, predicted 1
      0.1, 0.8, 0.1,        // truth 1, predicted 1
      0.3, 0.3, 0.4,        // truth 1, predicted 2
      0.1, 0.1, 0.8,        // truth 2, predicted 2
      0.5, 0.5, 0.0;        // truth 2, predicted 0 (tie)
  return score_classes({0, 0, 1, 1, 2, 2}, scores, {"berry", "branch", "leaf"});
}

TEST(ClassScores, ConfusionPerClassScoresAccuracyAndMiou) {
  const ClassScores s = hand_case();
  Eigen::MatrixXi want(3, 3);
  want << 1, 1, 0, 0, 1, 1, 1, 0, 1;
  EXPECT_EQ(s.confusion, want);
  EXPECT_EQ(s.points, 6u);
  EXPECT_DOUBLE_EQ(s.accuracy, 0.5);
  for (int c = 0; c < 3; ++c) {
    EXPECT_DOUBLE_EQ(s.precision[c], 0.5);
    EXPECT_DOUBLE_EQ(s.recall[c], 0.5);
    EXPECT_DOUBLE_EQ(s.iou[c], 1.0 / 3);  // 1 / (2 + 2 - 1)
  }
  EXPECT_DOUBLE_EQ(s.miou, 1.0 / 3);
}

TEST(ClassScores, RocCurveAndAucCountTiesAsHalf) {
  const ClassScores s = hand_case();
  // Berry: positives 0.9, 0.2 against 0.1, 0.3, 0.1, 0.5: 6 of 8 pairs ordered.
  EXPECT_EQ(s.roc[0].fpr, (std::vector<double>{0, 0, 0.25, 0.5, 0.5, 1}));
  EXPECT_EQ(s.roc[0].tpr, (std::vector<double>{0, 0.5, 0.5, 0.5, 1, 1}));
  EXPECT_DOUBLE_EQ(s.auc[0], 0.75);
  // Leaf: positives 0.8, 0.0 against 0.0, 0.1, 0.1, 0.4: 4 pairs plus a tie, 4.5 of 8.
  EXPECT_DOUBLE_EQ(s.auc[2], 4.5 / 8);
  EXPECT_TRUE(std::isnan(roc_auc(roc_curve({0.5, 0.7}, {true, true}))));  // no negatives
  EXPECT_DOUBLE_EQ(roc_auc(roc_curve({0.1, 0.9}, {false, true})), 1);
}

TEST(ClassScores, PerCaseMiouAveragesCasesAndBadInputThrows) {
  ClassScores a, b;
  a.miou = 1.0 / 3;
  b.miou = 1;
  EXPECT_DOUBLE_EQ(mean_case_miou({a, b}), 2.0 / 3);
  EXPECT_THROW(score_classes({0, 3}, Eigen::MatrixXd::Zero(2, 3), {"a", "b", "c"}), std::invalid_argument);
  EXPECT_THROW(score_classes({0}, Eigen::MatrixXd::Zero(2, 3), {"a", "b", "c"}), std::invalid_argument);
}

}  // namespace
}  // namespace grapebench
