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
};

struct CheckResult {
  bool pass = true;
  int rows_compared = 0;
  std::string diff;  // human-readable, one line per regression or missing row
};

// Rows match on (condition, estimator, quantity); a baseline row missing from the run
// is a regression, a new row in the run is reported but passes. Throws InputError
// (naming the file by `run_name` or `baseline_name` and the key) when either is not a
// summary, has no rows, or the two are of different scenes.
CheckResult check_against_baseline(const nlohmann::json& run_summary, const nlohmann::json& baseline,
                                   const std::string& run_name = "run", const std::string& baseline_name = "baseline");

}  // namespace grapebench
