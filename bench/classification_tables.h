// Seed 004's figures from a classification run (Dey et al. 2012): per condition and
// estimator, each classification row (auc_berry, accuracy, miou, berry_tpr, ...) as
// its mean over the cases (row sections) with the smallest and largest case.
#pragma once

#include <string>
#include <vector>

#include "bench/case_result.h"

namespace grapebench {

struct ClassificationCell {
  std::string condition, estimator, quantity;
  int cases = 0;  // cases whose row is ok
  double mean = 0, min = 0, max = 0;
};

// Cells in the order rows first appear; `labels` name each condition. Empty when no
// case has a classification row.
std::vector<ClassificationCell> classification_cells(const std::vector<CaseResult>& cases,
                                                     const std::vector<std::string>& labels);

// Per estimator (in first-seen order), the mean over the condition's cases of its ROC
// curve of `class_name` on the kRocGrid (vertical averaging, Fawcett 2006).
std::vector<std::pair<std::string, std::vector<double>>> mean_roc(const std::vector<CaseResult>& cases, int condition,
                                                                  const std::string& class_name);

// Per estimator, the confusion matrices of the condition's cases summed (pooled over
// every test point), with the accuracy and mIoU of the pooled matrix.
struct PooledConfusion {
  std::string estimator;
  std::vector<std::string> classes;
  std::vector<long long> counts;  // K x K, rows true
  double accuracy = 0, miou = 0;
};
std::vector<PooledConfusion> pooled_confusion(const std::vector<CaseResult>& cases, int condition);

// True for the rows the classification protocol writes.
bool is_classification_row(const std::string& quantity);

}  // namespace grapebench
