// CH: 3-D convex hull volume (seed 000: the fast convex hull algorithm, Barber et al.
// 1996; here CGAL's quickhull).
#pragma once

#include "algorithms/volume_estimate.h"
#include "algorithms/point_cloud.h"

namespace grapebench {

// Volume of the convex hull, with the hull as a closed mesh. Throws InputError for
// fewer than 4 points, non-finite points, or coplanar points.
VolumeEstimate convex_hull_volume(const PointCloud& cloud);

}  // namespace grapebench
