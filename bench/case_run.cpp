#include "bench/case_run.h"

#include "bench/protocols/registry.h"

namespace grapebench {

CaseResult run_case(const Condition& condition, int condition_index, const BunchJob& job) {
  return protocol_registry().make(condition.scene.protocol)(condition, condition_index, job);
}

}  // namespace grapebench
