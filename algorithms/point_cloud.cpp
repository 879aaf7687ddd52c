#include "algorithms/point_cloud.h"

#include <Eigen/Eigenvalues>

#include <sstream>

namespace grapebench {

PointCloud to_point_cloud(const std::vector<Vec3>& points) {
  PointCloud c(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) c.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  return c;
}

void require_points(const PointCloud& cloud, Eigen::Index min_points, const std::string& who) {
  if (cloud.rows() < min_points) {
    throw InputError(who + ": needs at least " + std::to_string(min_points) + " points, got " +
                     std::to_string(cloud.rows()));
  }
  for (Eigen::Index i = 0; i < cloud.rows(); ++i) {
    if (!cloud.row(i).allFinite()) throw InputError(who + ": point " + std::to_string(i) + " is not finite (NaN or inf)");
  }
}

}  // namespace grapebench

namespace grapebench {

void require_solid(const PointCloud& cloud, const std::string& who) {
  require_points(cloud, 4, who);
  const Eigen::RowVector3d mean = cloud.colwise().mean();
  const PointCloud c = cloud.rowwise() - mean;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(c.transpose() * c);
  const Eigen::Vector3d ev = eig.eigenvalues().cwiseMax(0.0);  // ascending
  if (ev[2] <= 0 || std::sqrt(ev[0] / ev[2]) < 1e-9) {
    throw InputError(who + ": the points are coplanar (or collinear); a volume needs a 3-D cloud");
  }
}

}  // namespace grapebench
