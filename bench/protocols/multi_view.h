// The multi_view protocol (seeds 000, 002): the views of a scan become one registered
// bunch cloud, measured by every estimator. Named stages: scan (capture.h), segment,
// register, merge, filter, estimate.
#pragma once

#include "bench/case_result.h"

namespace grapebench {

CaseResult run_multi_view(const Condition& condition, int condition_index, const BunchJob& job);

}  // namespace grapebench
