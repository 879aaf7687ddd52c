// Bring your own estimator: an external program that reads a cloud and answers in
// JSON (the protocol is in algorithms/README.md; an Open3D example is in
// scripts/external/open3d_estimator.py).
#pragma once

#include "algorithms/estimate.h"
#include "synth/param_table.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace grapebench {

struct ExternalParams {
  // Program and arguments, run without a shell (execvp: argv[0] is looked up in PATH).
  // "{scene_dir}" in an argument is replaced by the scene file's folder. The request
  // file's path is appended as the last argument.
  std::vector<std::string> command;
  std::vector<Quantity> quantities{Quantity::Volume};  // what the answer must hold
  double timeout = 300;  // s, [0.1, 86400]; the program is killed after it
  nlohmann::ordered_json params = nlohmann::ordered_json::object();  // passed through to the program
};
const ParamTable<ExternalParams>& external_param_table();
// Replaces every "{scene_dir}" in the command's arguments by `scene_dir` ("." when empty).
void substitute_scene_dir(std::vector<std::string>& command, const std::string& scene_dir);

// Writes `cloud.ply` (binary, x y z as doubles, metres) and `request.json` into a fresh
// temporary folder, runs the program, and reads `answer.json`:
//   {"volume": m3, "height": m, ..., "watertight": bool, "notes": "..."}.
// Throws InputError when the program cannot be started, exits non-zero (with the
// tail of its stderr), times out, or answers without a requested quantity.
Estimate external_estimate(const PointCloud& cloud, const ExternalParams& params);

}  // namespace grapebench
