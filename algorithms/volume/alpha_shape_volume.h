// AS: 3-D alpha shape volume of seed 000 (Edelsbrunner et al. 1983).
#pragma once

#include "algorithms/point_cloud.h"
#include "synth/param_table.h"
#include "algorithms/volume_estimate.h"

namespace grapebench {

struct AlphaShapeParams {
  // Alpha as a ball radius in metres (CGAL's alpha is its square), range [1e-4, 10].
  // Seed 000 gives "alpha = 0.25" without a unit. Read in metres it reproduces the
  // convex hull of a 0.2 m bunch, yet the paper's AS is 45 % below its CH
  // (835.7 vs 1537.4 cm3 on average), so the default reads 0.25 in decimetres: a
  // radius of 0.025 m, about one table-grape berry. Sweep it.
  double alpha = 0.025;
};
const ParamTable<AlphaShapeParams>& alpha_shape_param_table();

// Volume of the solid alpha complex (the interior tetrahedra of the Delaunay
// triangulation at this alpha, CGAL's Fixed_alpha_shape_3), with its boundary
// (the regular facets) as the mesh. Throws InputError for fewer than 4 points,
// non-finite or coplanar points, or an alpha outside its range.
VolumeEstimate alpha_shape_volume(const PointCloud& cloud, const AlphaShapeParams& params = {});

}  // namespace grapebench
