#include "bench/case_run.h"

#include "bench/protocols/registry.h"

namespace grapebench {

CaseResult run_case(const Condition& condition, int condition_index, const BunchJob& job) {
  return protocol_registry().make(condition.scene.protocol).run(condition, condition_index, job);
}

bool protocol_runs_together(const std::string& protocol) {
  return static_cast<bool>(protocol_registry().make(protocol).run_together);
}

std::vector<CaseResult> run_cases_together(std::span<const Condition* const> conditions,
                                           std::span<const int> condition_indices, const BunchJob& job) {
  if (conditions.empty()) return {};
  const ProtocolRun p = protocol_registry().make(conditions.front()->scene.protocol);
  if (!p.run_together || conditions.size() == 1) {
    std::vector<CaseResult> out;
    for (std::size_t c = 0; c < conditions.size(); ++c) out.push_back(p.run(*conditions[c], condition_indices[c], job));
    return out;
  }
  return p.run_together(conditions, condition_indices, job);
}

}  // namespace grapebench
