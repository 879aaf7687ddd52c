// `grapebench check`: a run's summary.json against a committed baseline.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace grapebench {

// Allowed worsening per metric before a row counts as a regression. A baseline file
// may carry its own under "tolerances" (same keys).
struct Tolerances {
  double rmse_rel = 0.05;          // RMSE may grow by 5 % of the baseline's
  double rmse_abs = 1e-6;          // plus this (display units), for RMSE near 0
  double mape_pct_abs = 0.5;       // MAPE may grow by 0.5 percentage points
  double r2_abs = 0.02;            // R2 may drop by 0.02
  double bias_rmse_frac = 0.1;     // |bias| may grow by 10 % of the baseline RMSE
  double success_rate_abs = 0.0;   // no case may newly fail
  // Seed 004's `classification` rows (AUCs, accuracy, mIoU, IoUs, rates: fractions):
  // a row's mean over the cases may worsen by this.
  double classification_abs = 0.01;
  // Seed 001's `stereo` tables: a cut-success rate or a depth cell's berries-found
  // rate may drop by this (fractions); a depth cell's mean |e_z| or |e_x| may grow by
  // cut_error_mm_abs (mm).
  double stereo_rate_abs = 0.0;
  double cut_error_mm_abs = 0.5;
};

struct CheckResult {
  bool pass = true;
  int rows_compared = 0;
  std::string diff;  // human-readable, one line per regression or missing row
};

// Rows match on (condition, estimator, quantity); a baseline row missing from the run
// is a regression, a new row in the run is reported but passes. The same holds for the
// `classification` rows (matched on condition, estimator, quantity; their mean) and
// the `stereo` tables (cut_success on condition and estimator; depth on estimator and
// depth_mm). Throws InputError (naming the file by `run_name` or `baseline_name` and
// the key) when either is not a summary, has no rows in any section, the two are of
// different scenes, or a tolerance is unknown, negative or not finite.
CheckResult check_against_baseline(const nlohmann::json& run_summary, const nlohmann::json& baseline,
                                   const std::string& run_name = "run", const std::string& baseline_name = "baseline");

}  // namespace grapebench
