// The protocol registry: how a case turns one bunch into rows of estimates. A scene
// names its protocol (`protocol: multi_view`); each is a runner made of named stages
// (bench/protocols/<name>.h). Adding one is its file pair, one line in registry.cpp
// and one CMake line.
#pragma once

#include "synth/registry.h"

#include <functional>
#include <span>
#include <vector>

namespace grapebench {

struct Condition;
struct BunchJob;
struct CaseResult;

// Runs one case; failures of a stage are recorded in the result, not thrown.
using CaseRun = std::function<CaseResult(const Condition& condition, int condition_index, const BunchJob& job)>;
// Runs one bunch's cases under several conditions at once, in their order, each the
// same as its CaseRun gives: the conditions' scenes differ only in sensors that share a
// together_key (sensors/sensor.h), so each view is captured once for all of them.
using CasesRun = std::function<std::vector<CaseResult>(std::span<const Condition* const> conditions,
                                                       std::span<const int> condition_indices, const BunchJob& job)>;
struct ProtocolRun {
  CaseRun run;
  CasesRun run_together;  // empty: the protocol runs its cases one by one
};

const Registry<ProtocolRun>& protocol_registry();

}  // namespace grapebench
