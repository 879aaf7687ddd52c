// Seed 003's accuracy measure and Table II: Err_x = |G_x - G_GT| w_e (Eq. 3), per
// frame and region, from the size_major / size_minor rows of single-frame runs.
#pragma once

#include "bench/case_result.h"
#include "bench/scene.h"

#include <array>
#include <string>
#include <vector>

namespace grapebench {

struct SizeErrorParams {
  std::array<double, 2> weights{0.5, 0.5};  // w_e; seed 003: [0.5 0.5]
  double filter = 0.10;                     // m: the "Filter" rows keep Err below this; seed 003: 10 cm
};

// One cell pair of Table II: an estimator on one ROI kind, over a set of conditions.
struct SizeErrorCell {
  std::string estimator, roi;
  int condition = -1;   // -1: every condition pooled (Table II), else that condition (Figs. 8-9)
  int regions = 0;      // ROIs whose fit gave both measures ("All")
  int failed = 0;       // ROIs whose fit failed (not in All)
  double mean = 0, sd = 0;                 // m, over All
  int kept = 0;                            // Err below the filter
  double kept_mean = 0, kept_sd = 0;       // m, over the kept
  double precision_mean = 0;               // mean fraction of the tuned region on the bunch
};

// Cells pooled over all conditions, then per condition, for every (estimator, ROI
// kind) with size rows; empty when the run has none.
std::vector<SizeErrorCell> size_error_cells(const SceneSet& set, const std::vector<CaseResult>& cases,
                                            const SizeErrorParams& p = {});

// One Table II entry, "mean +- sd (n)" in cm: All (filtered false) or Filter; "-" when
// no ROI counts.
std::string size_error_entry(const SizeErrorCell& cell, bool filtered);

// Table II's layout (markdown): estimators x (All, Filter) rows, ROI kinds as columns,
// "mean +- sd cm (n)".
std::string size_error_table(const std::vector<SizeErrorCell>& cells);
// Every cell as CSV (cm).
std::string size_error_csv(const SceneSet& set, const std::vector<SizeErrorCell>& cells);

}  // namespace grapebench
