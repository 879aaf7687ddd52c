// The self-contained HTML report of a run, with its plots as SVG.
#pragma once

#include "bench/case_scores.h"
#include "bench/size_error.h"

#include <map>
#include <string>

namespace grapebench {

struct Report {
  std::string html;                          // inline SVG, no external files or scripts
  std::map<std::string, std::string> svgs;   // the same plots as files: name -> SVG text
};

// Plots: estimated vs true per estimator and quantity, error vs each swept
// parameter, time per estimator; tables of scores and registration.
// With single-frame size rows (seed 003): Table II and its error by condition (Figs. 8-9).
Report make_report(const SceneSet& set, const std::vector<CaseResult>& cases, const std::vector<ScoreRow>& scores,
                   const std::vector<SizeErrorCell>& size_cells = {});

}  // namespace grapebench
