// The estimator registry: scene files name estimators by `type` (Mitsuba's `type=`,
// pbrt's Create). Adding an estimator is its file pair plus one line in registry.cpp.
#pragma once

#include "algorithms/filters.h"
#include "algorithms/point_cloud.h"
#include "synth/config.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace grapebench {

// Quantities an estimator can report, each scored against its ground truth.
// SI units inside the program (m3, m); the harness writes cm3 and mm.
// Perimeters are of the sections through the bunch centre normal to the height,
// length and width axis (seed 002 Eqs. 10-12).
// SizeMajor / SizeMinor: seed 003's pair of size measures G_x (Eq. 3), the larger and
// the smaller, scored against the hanging bunch's length and width, larger first.
enum class Quantity { Volume, Height, Length, Width, PerimeterH, PerimeterL, PerimeterW, SizeMajor, SizeMinor };
inline constexpr Quantity kAllQuantities[] = {Quantity::Volume,     Quantity::Height,     Quantity::Length,
                                              Quantity::Width,      Quantity::PerimeterH, Quantity::PerimeterL,
                                              Quantity::PerimeterW, Quantity::SizeMajor,  Quantity::SizeMinor};
const char* quantity_name(Quantity q);  // "volume", "height", ..., "perimeter_h"

// What one run of an estimator gives the harness.
struct Estimate {
  std::vector<std::pair<Quantity, double>> values;
  bool watertight = false;  // for volume methods with a mesh
  std::string notes;
};

// An estimator with its parameters bound (parsed and range-checked when the scene is
// read, so a bad parameter fails before any work starts). It gets the bunch's cloud
// (N x 3, m) and, one row per point in the same frame, the centre of the camera that
// saw the point (N x 3, m; empty where the pipeline does not know it).
using BoundEstimator = std::function<Estimate(const PointCloud& registered_bunch, const PointCloud& viewpoints)>;

struct EstimatorEntry {
  std::string type;
  std::string summary;  // one line: paper, equation, what it measures
  std::vector<Quantity> quantities;  // what it reports (rows even when it fails)
  // Reads the parameters from the scene's mapping (the harness reports unused keys)
  // and returns them with defaults filled, for the manifest.
  std::function<BoundEstimator(const ConfigNode& node, nlohmann::ordered_json& params)> create;
};

const std::vector<EstimatorEntry>& estimator_registry();
// The `quantities` an external estimator's scene entry declares (default: volume).
std::vector<Quantity> external_quantities(const ConfigNode& node);
std::vector<std::string> estimator_types();
// Looks up node["type"]; unknown types name file:line and the registered ones.
const EstimatorEntry& find_estimator(const ConfigNode& node);

// Pipeline steps on a point cloud (scene `pipeline.view_filters` / `cloud_filters`),
// registered like estimators: one line in registry.cpp per step.
using BoundFilter = std::function<FilteredCloud(const PointCloud& cloud)>;

struct FilterEntry {
  std::string type;
  std::string summary;
  std::function<BoundFilter(const ConfigNode& node, nlohmann::ordered_json& params)> create;
};

const std::vector<FilterEntry>& filter_registry();
std::vector<std::string> filter_types();
const FilterEntry& find_filter(const ConfigNode& node);

}  // namespace grapebench
