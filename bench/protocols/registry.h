// The protocol registry: how a case turns one bunch into rows of estimates. A scene
// names its protocol (`protocol: multi_view`); each is a runner made of named stages
// (bench/protocols/<name>.h). Adding one is its file pair, one line in registry.cpp
// and one CMake line.
#pragma once

#include "synth/registry.h"

#include <functional>

namespace grapebench {

struct Condition;
struct BunchJob;
struct CaseResult;

// Runs one case; failures of a stage are recorded in the result, not thrown.
using ProtocolRun = std::function<CaseResult(const Condition& condition, int condition_index, const BunchJob& job)>;

const Registry<ProtocolRun>& protocol_registry();

}  // namespace grapebench
