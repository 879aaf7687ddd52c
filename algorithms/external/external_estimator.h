// Bring your own estimator: an external program that reads what the protocol hands
// over and answers in JSON (the protocol is in algorithms/README.md and its JSON
// Schema in docs/external-protocol.schema.json; a Python example with Open3D and numpy
// is scripts/external/open3d_estimator.py).
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "synth/confined_program.h"
#include "algorithms/estimate.h"
#include "synth/param_table.h"

namespace grapebench {

class PersistentPrograms;

struct ExternalParams {
  // Program and arguments, run without a shell (execvp: argv[0] is looked up in PATH).
  // "{scene_dir}" in an argument is replaced by the scene file's folder. Per case, the
  // request file's path is appended as the last argument.
  std::vector<std::string> command;
  std::vector<Quantity> quantities{Quantity::Volume};  // what the answer must hold
  double timeout = 300;  // s, [0.1, 86400], the whole exchange of one request; then it and all it started are killed
  // Confinement (synth/confined_program.h): the sandbox and per-process limits.
  ProgramLimits::Sandbox sandbox = ProgramLimits::Sandbox::Bwrap;
  std::vector<std::string> readable;  // more it may read under bwrap ("{scene_dir}" replaced)
  double cpu_limit = 3600;    // s
  double memory_limit = 8192;  // MB of address space
  double file_limit = 1024;    // MB
  // 1: grapebench-estimator-1 (x y z only, a scalar answer; the default, so programs
  // written for it keep working); 2: grapebench-estimator-2 (every per-point attribute
  // and the views or frame; every output kind).
  int version = 1;
  // Version 2 only. false: one process per request; true: one process answers many
  // requests, a JSON line each on stdin, an answer line each on stdout (Python's
  // start-up and imports paid once per run and thread, not per case).
  bool persistent = false;
  // Version 2 only. What the program measures: the protocol's cloud, a rectified
  // colour stereo pair (protocol stereo_pair: left.png, right.png and the camera), or a
  // coloured cloud with training labels to score per point (protocol classification:
  // `classes`, `train_labels`; the answer is `class_scores`, no scalar).
  enum class Input { Cloud, StereoPair, LabelledCloud, Image };
  Input input = Input::Cloud;
  nlohmann::ordered_json params = nlohmann::ordered_json::object();  // passed through to the program
  // Who answers, in messages: empty for "external estimator '<command[0]>'" (the
  // Python estimator names its function).
  std::string who;
  // The running programs of persistent mode (set when the estimator is created).
  std::shared_ptr<PersistentPrograms> programs;
};
const ParamTable<ExternalParams>& external_param_table();
// Replaces every "{scene_dir}" in the command's arguments by `scene_dir` ("." when empty).
void substitute_scene_dir(std::vector<std::string>& command, const std::string& scene_dir);
// The process pool of persistent mode; its processes end when the last copy of the
// returned pointer goes (stdin closed, then the group killed after 2 s).
std::shared_ptr<PersistentPrograms> start_persistent_programs(const ExternalParams& params);

// Writes the request's files into a fresh temporary folder, runs the program (or asks
// a persistent one) and checks its answer:
//   {"volume": m3, "height": m, ..., "points": {"name": [x, y, z]},
//    "detections": [{"x": px, "y": px, "r": px, "score": s}], "class_scores": [[...] per point],
//    "watertight": bool, "notes": "..."}, or {"error": "why"} to fail that request.
// Every requested quantity must be a finite number in (0, 1000] (m3 or m). Throws
// InputError when the program cannot be started, exits non-zero (with the tail of its
// stderr), times out, or answers outside the protocol.
Estimate external_estimate(const EstimatorInput& input, const ExternalParams& params);

// The answer checked against the request (exposed for tests): `points` is the number
// of input points (rows of class_scores).
// input_width, input_height: the image of input: image (its masks' size), else 0.
Estimate parse_external_answer(const nlohmann::json& answer, const ExternalParams& params, long points,
                               int input_width = 0, int input_height = 0);

// The scene's name of an input kind ("cloud", "stereo_pair", "labelled_cloud", "image").
const char* external_input_name(ExternalParams::Input input);
// InputError unless the protocol's hand-over holds what p.input needs (also for
// algorithms/external/python_estimator.h).
void require_external_input(const EstimatorInput& input, const ExternalParams& p);
// `e` back, or InputError when a classifier's answer lacks a score per point and class.
Estimate require_class_scores(Estimate e, const EstimatorInput& input, const ExternalParams& p);

}  // namespace grapebench
