#include "bench/scoring/classes.h"

#include "bench/scoring/rates.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace grapebench {

RocCurve roc_curve(const std::vector<double>& score, const std::vector<bool>& positive) {
  if (score.size() != positive.size()) throw std::invalid_argument("roc_curve: score and truth sizes differ");
  std::vector<std::size_t> order(score.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return score[a] > score[b]; });
  const double pos = static_cast<double>(std::count(positive.begin(), positive.end(), true));
  const double neg = static_cast<double>(positive.size()) - pos;
  RocCurve c;
  c.fpr.push_back(0);
  c.tpr.push_back(0);
  c.threshold.push_back(std::numeric_limits<double>::infinity());
  double tp = 0, fp = 0;
  for (std::size_t k = 0; k < order.size();) {
    const double s = score[order[k]];
    for (; k < order.size() && score[order[k]] == s; ++k) (positive[order[k]] ? tp : fp) += 1;
    c.fpr.push_back(neg > 0 ? fp / neg : 0);
    c.tpr.push_back(pos > 0 ? tp / pos : 0);
    c.threshold.push_back(s);
  }
  return c;
}

double roc_auc(const RocCurve& c) {
  if (c.fpr.empty() || c.fpr.back() <= 0 || c.tpr.back() <= 0) return kNaN;
  double area = 0;
  for (std::size_t k = 1; k < c.fpr.size(); ++k) area += (c.fpr[k] - c.fpr[k - 1]) * 0.5 * (c.tpr[k] + c.tpr[k - 1]);
  return area;
}

ClassScores score_classes(const std::vector<int>& truth, const Eigen::MatrixXd& scores,
                          const std::vector<std::string>& classes) {
  const int k = static_cast<int>(classes.size());
  if (scores.rows() != static_cast<Eigen::Index>(truth.size()) || scores.cols() != k) {
    throw std::invalid_argument("score_classes: scores must be N x K for N labels and K classes");
  }
  ClassScores s;
  s.classes = classes;
  s.points = truth.size();
  s.confusion = Eigen::MatrixXi::Zero(k, k);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (truth[i] < 0 || truth[i] >= k) throw std::invalid_argument("score_classes: a label outside [0, K)");
    Eigen::Index predicted = 0;
    scores.row(static_cast<Eigen::Index>(i)).maxCoeff(&predicted);  // first maximum: lowest index on ties
    ++s.confusion(truth[i], predicted);
  }
  int defined = 0;
  double iou_sum = 0;
  for (int c = 0; c < k; ++c) {
    const double tp = s.confusion(c, c), predicted = s.confusion.col(c).sum(), actual = s.confusion.row(c).sum();
    s.precision.push_back(ratio(tp, predicted));
    s.recall.push_back(ratio(tp, actual));
    s.iou.push_back(ratio(tp, predicted + actual - tp));
    if (std::isfinite(s.iou.back())) {
      iou_sum += s.iou.back();
      ++defined;
    }
    std::vector<double> score(truth.size());
    std::vector<bool> positive(truth.size());
    for (std::size_t i = 0; i < truth.size(); ++i) {
      score[i] = scores(static_cast<Eigen::Index>(i), c);
      positive[i] = truth[i] == c;
    }
    s.roc.push_back(roc_curve(score, positive));
    s.auc.push_back(roc_auc(s.roc.back()));
  }
  s.accuracy = ratio(s.confusion.trace(), static_cast<double>(s.points));
  s.miou = defined > 0 ? iou_sum / defined : kNaN;
  return s;
}

double mean_case_miou(const std::vector<ClassScores>& cases) {
  double sum = 0;
  int n = 0;
  for (const auto& c : cases) {
    if (!std::isfinite(c.miou)) continue;
    sum += c.miou;
    ++n;
  }
  return n > 0 ? sum / n : kNaN;
}

}  // namespace grapebench
