// Scores of a run's cases per condition and estimator (summary.json, leaderboard,
// report) and the registration and segmentation scores per condition.
#pragma once

#include "bench/case_result.h"
#include "bench/scene.h"
#include "bench/scoring/scalars.h"
#include "bench/scoring/statistics.h"

#include <string>
#include <vector>

namespace grapebench {

// One line of the scores table (summary.json, leaderboard, report).
struct ScoreRow {
  int condition = 0;
  std::string estimator, type, quantity;
  Score score;
  double peak_heap_mb_max = 0;  // largest peak heap of one run, MB (NaN: not measured); not deterministic
  ScoreIntervals intervals;     // 95 % BCa bootstrap intervals, seeded from the scene's seed
  double concordance = 0;       // Lin's CCC of estimate and truth
  Agreement agreement;          // Bland-Altman mean difference and limits
  // Per measurement ("bunch/frame/region"): estimate and truth, display units, of the
  // successful rows (paired comparisons, Bland-Altman plots).
  std::vector<std::string> keys;
  std::vector<double> estimates, truths;
};
std::vector<ScoreRow> score_cases(const SceneSet& set, const std::vector<CaseResult>& cases);

// Every two estimators of a condition that measure the same quantity (and, single-frame,
// the same ROI kind), on the measurements both made: |error of a| - |error of b|.
struct ComparisonRow {
  int condition = 0;
  std::string quantity, a, b;
  PairedComparison comparison;
};
std::vector<ComparisonRow> paired_comparisons(const SceneSet& set, const std::vector<ScoreRow>& scores);

// Registration per condition over its successful cases (summary.json, report).
struct RegistrationRow {
  int cases = 0, failed = 0;
  double rotation_max_deg_mean = 0;   // mean over cases of the per-case worst view
  double rotation_max_deg_worst = 0;
  double translation_max_mm_mean = 0;
  // Means over the cases of the pipeline's label scores (case_run.h).
  double segmentation_precision = 0, segmentation_recall = 0, peduncle_kept = 0, body_kept = 0;
};
std::vector<RegistrationRow> registration_rows(const SceneSet& set, const std::vector<CaseResult>& cases);

}  // namespace grapebench
