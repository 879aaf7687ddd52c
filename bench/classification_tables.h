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

// True for the rows the classification protocol writes.
bool is_classification_row(const std::string& quantity);

}  // namespace grapebench
