// Scores of a scalar output (volume, a length) against the ground truth over a set of cases.
#pragma once

#include <string>
#include <vector>

namespace grapebench {

// Everything in display units (cm3 for volume, mm for lengths).
struct Score {
  int cases = 0;       // rows, including failures
  int succeeded = 0;   // rows with a finite estimate
  double success_rate = 0;
  double r2 = 0;          // squared Pearson correlation of estimate and truth (the papers' R2)
  double r2_identity = 0;  // 1 - SS_res / SS_tot about the line estimate = truth
  double rmse = 0, mae = 0, bias = 0;  // estimate - truth
  double mape = 0;                    // mean |error| / truth, percent
  double slope = 1, intercept = 0;    // least-squares fit estimate = slope * truth + intercept
  double time_median = 0, time_p25 = 0, time_p75 = 0;  // seconds per run
};

// `estimate`, `truth` of the successful rows; `seconds` of every row that ran.
// Statistics that need two or more distinct values are NaN otherwise.
Score score(const std::vector<double>& estimate, const std::vector<double>& truth, int cases,
            const std::vector<double>& seconds);

// Linearly interpolated quantile q in [0, 1] of v; NaN when v is empty.
double quantile(std::vector<double> v, double q);

// Display unit and scale from SI for a quantity name.
const char* display_unit(const std::string& quantity);
double display_scale(const std::string& quantity);

}  // namespace grapebench
