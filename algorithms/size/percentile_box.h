// Percentile bounding box (seed 003 Algorithm 1): per axis of the cloud's frame, the
// alpha and 1 - alpha percentiles of the coordinates.
#pragma once

#include "algorithms/point_cloud.h"
#include "synth/param_table.h"

#include <array>

namespace grapebench {

struct PercentileBoxParams {
  // Percentile fraction, [0, 0.5). Seed 003 writes alpha = 0.02 but describes the 20th
  // and 80th percentiles (alpha = 0.2); the default follows the written value.
  double alpha = 0.02;
};
const ParamTable<PercentileBoxParams>& percentile_box_param_table();

struct PercentileBox {
  Vec3 minimum = Vec3::Zero(), maximum = Vec3::Zero();  // m, per axis of the input frame
  std::array<double, 3> edges{};      // m, sorted, largest first
  // m, face diagonals sqrt(e_i^2 + e_j^2), largest first. Seed 003's G_D is "the two
  // largest diagonals (representing X and Y)"; this reads them as face diagonals.
  std::array<double, 3> diagonals{};
  double volume() const { return edges[0] * edges[1] * edges[2]; }  // m3, from the three edges
};

// Percentiles by linear interpolation between order statistics (MATLAB's prctile
// differs by at most one sample spacing). Throws InputError for fewer than 2 points,
// non-finite points or alpha outside [0, 0.5).
PercentileBox percentile_box(const PointCloud& cloud, const PercentileBoxParams& params = {});

}  // namespace grapebench
