// Scores of a per-point classification output (seed 004: berry, branch, leaf) against
// the exact labels: confusion matrix, per-class precision, recall and IoU, overall
// accuracy, mIoU, and per class the one-vs-rest ROC curve and its AUC from the scores.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace grapebench {

// One-vs-rest ROC: points (false positive rate, true positive rate) from (0, 0) to
// (1, 1), one per distinct score, taken from the highest score down.
struct RocCurve {
  std::vector<double> fpr, tpr;
  std::vector<double> threshold;  // the score at which each point is reached (+inf for (0, 0))
};

// `positive[i]` is point i's truth; scores of tied points enter together, so the AUC
// is the Mann-Whitney probability that a positive outscores a negative, ties counted
// one half. Throws std::invalid_argument when the sizes differ.
RocCurve roc_curve(const std::vector<double>& score, const std::vector<bool>& positive);
// Trapezoidal area under the curve; NaN without positives or without negatives.
double roc_auc(const RocCurve& curve);

struct ClassScores {
  std::vector<std::string> classes;  // K
  Eigen::MatrixXi confusion;         // K x K: rows true class, columns predicted class
  std::size_t points = 0;
  std::vector<double> precision, recall, iou;  // per class; NaN where the denominator is 0
  double accuracy = 0;  // correct / points
  // Mean of the per-class IoU over the classes where it is defined, pooled over the
  // points given (one case, or every case's points together).
  double miou = 0;
  std::vector<RocCurve> roc;  // per class, one vs rest
  std::vector<double> auc;
};

// truth: N class indices in [0, K); scores: N x K, higher meaning more likely (the
// predicted class is the row's argmax, the lowest index on ties).
ClassScores score_classes(const std::vector<int>& truth, const Eigen::MatrixXd& scores,
                          const std::vector<std::string>& classes);

// mIoU averaged per case (each case's own mIoU, then their mean), beside the pooled one.
double mean_case_miou(const std::vector<ClassScores>& cases);

}  // namespace grapebench
