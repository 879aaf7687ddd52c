// Size in the bunch's own PCA frame (seed 000, Eq. 5; seed 002, Eqs. 7-9).
#pragma once

#include "algorithms/point_cloud.h"

namespace grapebench {

struct PcaBox {
  Vec3 centre = Vec3::Zero();                              // mean of the points, m
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();      // columns: decreasing variance
  Vec3 minimum = Vec3::Zero(), maximum = Vec3::Zero();     // box corners in the PCA frame, m
  // Seed 000: the eigenvector of the largest eigenvalue is the Z axis, so
  // h = z_max - z_min along it; l along the second axis, w along the third (Eq. 5).
  double height = 0, length = 0, width = 0;  // m
  double volume() const { return height * length * width; }  // box volume from the three edges, m3
};

// Covariance of the mean-centred cloud, its eigenvectors (seed 000 Eqs. 1-2), then
// the min/max extents of the points along them. Throws InputError for fewer than 3
// points, non-finite points, or all points coincident.
PcaBox pca_box(const PointCloud& cloud);

}  // namespace grapebench
