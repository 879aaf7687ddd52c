// Algebraic least-squares ellipsoid fit (seed 003 Sect. II-B3, after Petrov's MATLAB
// "ellipsoid_fit"): the quadric A x^2 + B y^2 + C z^2 + 2D xy + 2E xz + 2F yz + 2G x +
// 2H y + 2I z = 1 through the points, then its centre, axes and radii.
#pragma once

#include "algorithms/point_cloud.h"
#include "synth/param_table.h"

namespace grapebench {

struct EllipsoidFit {
  Vec3 centre = Vec3::Zero();                     // m
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // columns: unit axes, radii decreasing
  Vec3 radii = Vec3::Zero();                      // m, largest first; seed 003's G_R is the two largest
  double rms_residual = 0;                        // RMS of the algebraic residual
};

// Throws InputError for fewer than 9 points, non-finite points, a degenerate system
// (e.g. coplanar points) or a quadric that is not an ellipsoid (the single-view case
// the paper warns about can give a hyperboloid).
EllipsoidFit ellipsoid_fit(const PointCloud& cloud);

// What G_R reports: seed 003 compares the radii themselves with the cluster's length
// and width; `diameters` doubles them (the like-for-like reading).
struct EllipsoidSizeParams {
  enum class Measure { Radii, Diameters };
  Measure measure = Measure::Radii;
};
const ParamTable<EllipsoidSizeParams>& ellipsoid_size_param_table();

}  // namespace grapebench
