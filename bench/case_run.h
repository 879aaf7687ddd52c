// One case of a run: one bunch under one condition, from generation to scores.
#pragma once

#include "bench/case_result.h"
#include "bench/scene.h"

namespace grapebench {

// Runs a case through the scene's protocol (bench/protocols/); errors of the bunch's
// scan, a stage or an estimator are recorded, not thrown.
CaseResult run_case(const Condition& condition, int condition_index, const BunchJob& job);

// Whether `protocol` runs a bunch's cases under several conditions at once.
bool protocol_runs_together(const std::string& protocol);
// One bunch's cases under `conditions` (one protocol; scenes that differ only in
// sensors with one together_key) at once, in their order, each the same as run_case's.
std::vector<CaseResult> run_cases_together(std::span<const Condition* const> conditions,
                                           std::span<const int> condition_indices, const BunchJob& job);

}  // namespace grapebench
