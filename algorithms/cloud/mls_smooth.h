// MLS smoothing with normals (seed 000, Eqs. 3-4; PCL's MovingLeastSquares).
#pragma once

#include "algorithms/point_cloud.h"
#include "synth/param_table.h"

#include <vector>

namespace grapebench {

struct MlsParams {
  // Neighbourhood radius, m, [1e-4, 0.5]. Seed 000 does not give it; 10 mm covers
  // the Kinect's 1-2 mm noise at 1 m with tens of neighbours.
  double radius = 0.01;
  int polynomial_order = 2;  // seed 000 Eq. 3: a second-order surface, [0, 4]
};
const ParamTable<MlsParams>& mls_param_table();

struct SmoothedCloud {
  PointCloud points;   // N x 3, m (projected onto the local polynomial)
  PointCloud normals;  // N x 3, unit, oriented away from the cloud's centroid
  std::vector<Eigen::Index> source;  // N: the input row each point was projected from
};

// Points with fewer than 3 neighbours inside the radius are dropped. Throws
// InputError for fewer than 4 points or non-finite points, or a radius out of range.
SmoothedCloud mls_smooth(const PointCloud& cloud, const MlsParams& params = {});

}  // namespace grapebench
