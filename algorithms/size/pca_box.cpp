#include "algorithms/size/pca_box.h"

#include <Eigen/Eigenvalues>

namespace grapebench {

PcaBox pca_box(const PointCloud& cloud) {
  require_points(cloud, 3, "pca_box");
  PcaBox b;
  b.centre = cloud.colwise().mean().transpose();
  const PointCloud centred = cloud.rowwise() - b.centre.transpose();
  const Eigen::Matrix3d cov = centred.transpose() * centred / static_cast<double>(cloud.rows());
  if (cov.trace() <= 0) throw InputError("pca_box: all points coincide");
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  for (int k = 0; k < 3; ++k) {
    Vec3 a = eig.eigenvectors().col(2 - k);
    int big = 0;
    a.cwiseAbs().maxCoeff(&big);
    if (a[big] < 0) a = -a;  // deterministic sign
    b.axes.col(k) = a;
  }
  b.axes.col(2) = b.axes.col(0).cross(b.axes.col(1));
  const Eigen::Matrix<double, Eigen::Dynamic, 3> local = centred * b.axes;
  b.minimum = local.colwise().minCoeff().transpose();
  b.maximum = local.colwise().maxCoeff().transpose();
  const Vec3 e = b.maximum - b.minimum;
  b.height = e[0];
  b.length = e[1];
  b.width = e[2];
  return b;
}

}  // namespace grapebench
