// N x 3 point clouds (m) as PCL's, for the translation units that call PCL (float
// coordinates, as PCL's search structures take them).
#pragma once

#include "algorithms/point_cloud.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace grapebench {

inline pcl::PointCloud<pcl::PointXYZ>::Ptr to_pcl(const PointCloud& c) {
  auto out = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  out->resize(static_cast<std::size_t>(c.rows()));
  for (Eigen::Index i = 0; i < c.rows(); ++i) {
    (*out)[static_cast<std::size_t>(i)] = pcl::PointXYZ(static_cast<float>(c(i, 0)), static_cast<float>(c(i, 1)),
                                                        static_cast<float>(c(i, 2)));
  }
  return out;
}

}  // namespace grapebench
