// What an estimator answers: the quantities it reports, as plain values in SI units.
#pragma once

#include "algorithms/point_cloud.h"

#include <functional>
#include <string>
#include <utility>
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
// (name, quantity) for every quantity: the choices of a scene's `quantities` list.
std::vector<std::pair<std::string, Quantity>> quantity_choices();

// What one run of an estimator gives the harness.
struct Estimate {
  std::vector<std::pair<Quantity, double>> values;
  bool watertight = false;  // for volume methods with a mesh
  std::string notes;        // diagnostics (points used, iterations, residuals), into results.csv
};

// An estimator with its parameters bound (parsed and range-checked when the scene is
// read, so a bad parameter fails before any work starts). It gets the bunch's cloud
// (N x 3, m) and, one row per point in the same frame, the centre of the camera that
// saw the point (N x 3, m; empty where the pipeline does not know it).
using BoundEstimator = std::function<Estimate(const PointCloud& registered_bunch, const PointCloud& viewpoints)>;

}  // namespace grapebench
