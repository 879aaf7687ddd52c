#include "algorithms/size/ellipsoid_fit.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace grapebench {

EllipsoidFit ellipsoid_fit(const PointCloud& cloud) {
  require_points(cloud, 9, "ellipsoid_fit");
  // Centred and scaled so the normal equations are well conditioned.
  const Eigen::RowVector3d mean = cloud.colwise().mean();
  const PointCloud c = cloud.rowwise() - mean;
  const double scale = std::sqrt(c.rowwise().squaredNorm().mean());
  if (!(scale > 0)) throw InputError("ellipsoid_fit: all points coincide");
  const Eigen::MatrixXd q = c / scale;
  const Eigen::Index n = q.rows();
  Eigen::MatrixXd d(n, 9);
  const auto x = q.col(0).array(), y = q.col(1).array(), z = q.col(2).array();
  d.col(0) = (x * x).matrix();
  d.col(1) = (y * y).matrix();
  d.col(2) = (z * z).matrix();
  d.col(3) = (2 * x * y).matrix();
  d.col(4) = (2 * x * z).matrix();
  d.col(5) = (2 * y * z).matrix();
  d.col(6) = (2 * x).matrix();
  d.col(7) = (2 * y).matrix();
  d.col(8) = (2 * z).matrix();
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(d);
  if (qr.rank() < 9) throw InputError("ellipsoid_fit: the points do not determine a quadric (coplanar or too few distinct)");
  const Eigen::VectorXd v = qr.solve(Eigen::VectorXd::Ones(n));
  // Quadric as a 4 x 4 matrix; its centre solves A3 c = -g.
  Eigen::Matrix4d a;
  a << v(0), v(3), v(4), v(6), v(3), v(1), v(5), v(7), v(4), v(5), v(2), v(8), v(6), v(7), v(8), -1;
  const Eigen::Matrix3d a3 = a.topLeftCorner<3, 3>();
  const Eigen::Vector3d centre = a3.ldlt().solve(-v.segment<3>(6));
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  t.block<1, 3>(3, 0) = centre.transpose();
  const Eigen::Matrix4d r = t * a * t.transpose();
  const double k = -r(3, 3);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(r.topLeftCorner<3, 3>() / k);
  const Eigen::Vector3d ev = eig.eigenvalues();
  if (!(ev.array() > 0).all()) {
    throw InputError("ellipsoid_fit: the best quadric is not an ellipsoid (eigenvalues of signs " +
                     std::string(ev(0) > 0 ? "+" : "-") + (ev(1) > 0 ? "+" : "-") + (ev(2) > 0 ? "+" : "-") +
                     "); a single view of a convex patch can fit a hyperboloid");
  }
  EllipsoidFit f;
  f.centre = mean.transpose() + scale * centre;
  // Radii 1/sqrt(eigenvalue): the smallest eigenvalue gives the largest radius.
  for (int i = 0; i < 3; ++i) {
    f.radii(i) = scale / std::sqrt(ev(i));
    f.axes.col(i) = eig.eigenvectors().col(i);
  }
  f.rms_residual = std::sqrt((d * v - Eigen::VectorXd::Ones(n)).squaredNorm() / static_cast<double>(n));
  return f;
}

const ParamTable<EllipsoidSizeParams>& ellipsoid_size_param_table() {
  using P = EllipsoidSizeParams;
  static const ParamTable<P> table = ParamTable<P>().choice(
      "measure", &P::measure, {{"radii", P::Measure::Radii}, {"diameters", P::Measure::Diameters}},
      "report the two largest radii (seed 003's G_R) or diameters");
  return table;
}

}  // namespace grapebench
