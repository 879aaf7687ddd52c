// Ellipsoid volume: 4/3 pi r1 r2 r3 of the algebraic least-squares ellipsoid through
// the points (algorithms/size/ellipsoid_fit.h, after seed 003's Petrov fit). The classic
// model of a fruit as an ellipsoid; on a bunch it stands for the envelope, concavities
// filled.
#pragma once

#include "algorithms/point_cloud.h"
#include "algorithms/volume_estimate.h"

namespace grapebench {

// Throws InputError where ellipsoid_fit does (fewer than 9 points, a degenerate or
// non-ellipsoid quadric). The notes give the three radii.
VolumeEstimate ellipsoid_volume(const PointCloud& cloud);

}  // namespace grapebench
