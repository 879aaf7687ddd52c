// One case of a run: one bunch under one condition, from generation to scores.
#pragma once

#include "bench/case_result.h"
#include "bench/scene.h"

namespace grapebench {

// Runs a case through the scene's protocol (bench/protocols/); errors of the bunch's
// scan, a stage or an estimator are recorded, not thrown.
CaseResult run_case(const Condition& condition, int condition_index, const BunchJob& job);

}  // namespace grapebench
