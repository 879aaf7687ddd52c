// Seed 001's tables from a stereo_pair run (Luo et al. 2016): Table 2 (cutting-point
// success by light condition, with Wilson 95 % intervals), Table 1 (berry detection
// rate by depth) and Fig. 11 (mean |e_z| and |e_x| of the cutting point by depth).
// Depth is the station's distance (rows' roi "station_0800mm"), binned to the paper's
// 100 mm steps (350-449 mm is "400").
#pragma once

#include <string>
#include <vector>

#include "bench/case_result.h"

namespace grapebench {

struct SuccessCell {
  std::string estimator, condition;
  int pairs = 0, successes = 0;
  double rate = 0, lo = 0, hi = 0;  // fraction and its Wilson 95 % interval
};
struct DepthCell {
  std::string estimator;
  int depth_mm = 0;  // bin centre
  int pairs = 0;
  int visible = 0, found = 0;   // berries (Table 1)
  int answered = 0;             // pairs with e_z and e_x
  double ez_mm = 0, ex_mm = 0;  // mean |error| over the answered pairs (Fig. 11)
};
struct StereoTables {
  std::vector<SuccessCell> success;
  std::vector<DepthCell> depth;
  bool empty() const { return success.empty(); }
};

// Wilson score interval of k successes in n trials at z = 1.96.
std::pair<double, double> wilson_interval(int k, int n);

// Rows of the cases' cut_success, cut_z, cut_x and berries_found; `labels` name each
// condition (its sweep label, or "all").
StereoTables stereo_tables(const std::vector<CaseResult>& cases, const std::vector<std::string>& labels);

}  // namespace grapebench
