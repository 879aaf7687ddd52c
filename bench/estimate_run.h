// `grapebench estimate`: registered estimators on a user's own point cloud (PLY or
// PCD), no scene, no truth: the numbers, their diagnostics and the run's time.
#pragma once

#include "bench/cloud_file.h"
#include "bench/progress.h"
#include "bench/scene.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace grapebench {

// The estimators named on the command line: a type ("alpha_shape") or a YAML flow
// mapping ("{type: alpha_shape, alpha: 0.02, name: AS}"); with none and no scene,
// every registered estimator that measures a cloud, with its defaults.
std::vector<EstimatorSpec> estimators_from_arguments(const std::vector<std::string>& arguments);
// The `estimators:` list of a scene file (its other sections are not read).
std::vector<EstimatorSpec> estimators_from_scene(const std::string& path);

// Runs each estimator on the cloud (points, and normals and colours when the file has
// them). The answer: {file, format, points, dropped_nan, has_normals, has_colours,
// estimators: [{name, type, ok, error, seconds, peak_heap_mb, values: {quantity:
// {value, unit}}, points: {name: [x, y, z]}, notes}]}, values in display units (cm3,
// mm), points in the file's units.
nlohmann::ordered_json estimate_cloud(const CloudFile& cloud, const std::string& file,
                                      const std::vector<EstimatorSpec>& estimators,
                                      Verbosity verbosity = Verbosity::quiet);
// The answer as a console table.
std::string estimate_table(const nlohmann::ordered_json& answer);

}  // namespace grapebench
