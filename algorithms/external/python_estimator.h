// An estimator written in Python, run in-process (issue 41): a scene's
// `{type: python, module: my_estimator, function: estimate}` calls
// my_estimator.estimate(request) on the input every built-in estimator gets, as numpy
// arrays, and reads its answer by the external protocol's rules
// (algorithms/external/external_estimator.h), so one Python function serves both. The request:
//   protocol "grapebench-estimator-2", kind, units "m", quantities [names], params {...},
//   cloud (N x 3 float64, m), points (N), attributes [names], normals / viewpoints
//   (N x 3 float64) and colours (N x 3 uint8) where listed, views [{name, pose (4 x 4),
//   cloud (M x 3), points}], frame {...}, classes and train_labels (N int64),
//   stereo or image {left, right (H x W x 3 uint8, right None when not rendered),
//   width, height, fx, fy, cx, cy, baseline}.
// Arrays are copies the function may keep. Under the `grapebench` command the
// interpreter is started in the process (Debian's /usr/bin/python3 libraries, the
// active VIRTUAL_ENV's packages); under `import grapebench` the caller's is used. The
// GIL is held for the call only, so the harness's other threads run meanwhile.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "algorithms/estimate.h"
#include "algorithms/external/external_estimator.h"
#include "synth/param_table.h"

namespace grapebench {

class PythonFunction;  // the imported function (a Python object, released under the GIL)

struct PythonParams {
  std::string module;                          // imported by name, e.g. my_estimator
  std::string function = "estimate";          // called as function(request) -> answer dict
  std::vector<std::string> path{"{scene_dir}"};  // folders put first on sys.path
  ExternalParams::Input input = ExternalParams::Input::Cloud;
  std::vector<Quantity> quantities{Quantity::Volume};
  nlohmann::ordered_json params = nlohmann::ordered_json::object();  // request["params"]
  std::shared_ptr<PythonFunction> callable;  // set when the estimator is created
};
const ParamTable<PythonParams>& python_param_table();

// Whether this build runs Python estimators (CMake's GRAPEBENCH_BUILD_PYTHON).
bool python_available();

// Imports p.module (p.path first on sys.path) and finds p.function: InputError with the
// exception's last lines when the import fails or the function is missing.
std::shared_ptr<PythonFunction> load_python_function(const PythonParams& p);

// Calls the function on `input`; an exception it raises, or an answer outside the
// protocol, is an InputError (the row fails with the traceback's tail).
Estimate python_estimate(const EstimatorInput& input, const PythonParams& p);

}  // namespace grapebench
