#include "algorithms/cloud/mls_smooth.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/mls.h>

#include <cmath>
#include <stdexcept>

namespace grapebench {

SmoothedCloud mls_smooth(const PointCloud& cloud, const MlsParams& p) {
  require_points(cloud, 4, "mls_smooth");
  if (!(p.radius >= 1e-4 && p.radius <= 0.5)) throw InputError("mls_smooth: radius must lie in [1e-4, 0.5] m");
  if (p.polynomial_order < 0 || p.polynomial_order > 4) throw InputError("mls_smooth: polynomial_order must lie in [0, 4]");
  // Centred on the centroid so single precision keeps sub-micrometre resolution.
  const Eigen::RowVector3d centre = cloud.colwise().mean();
  auto in = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  in->resize(static_cast<std::size_t>(cloud.rows()));
  for (Eigen::Index i = 0; i < cloud.rows(); ++i) {
    const Eigen::RowVector3d q = cloud.row(i) - centre;
    (*in)[static_cast<std::size_t>(i)] = pcl::PointXYZ(static_cast<float>(q(0)), static_cast<float>(q(1)), static_cast<float>(q(2)));
  }
  pcl::MovingLeastSquares<pcl::PointXYZ, pcl::PointNormal> mls;
  mls.setInputCloud(in);
  mls.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  mls.setSearchRadius(p.radius);
  mls.setPolynomialOrder(p.polynomial_order);
  mls.setComputeNormals(true);
  mls.setNumberOfThreads(1);  // deterministic
  pcl::PointCloud<pcl::PointNormal> out;
  mls.process(out);
  SmoothedCloud s;
  const auto corresponding = mls.getCorrespondingIndices();
  if (!corresponding || corresponding->indices.size() != out.size()) throw std::logic_error("mls_smooth: PCL gave no input index per output point");
  std::vector<Eigen::Index> keep;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto& q = out[i];
    if (std::isfinite(q.x) && std::isfinite(q.normal_x) && std::isfinite(q.y) && std::isfinite(q.z)) keep.push_back(static_cast<Eigen::Index>(i));
  }
  s.points.resize(static_cast<Eigen::Index>(keep.size()), 3);
  s.normals.resize(static_cast<Eigen::Index>(keep.size()), 3);
  for (std::size_t k = 0; k < keep.size(); ++k) {
    const auto& q = out[static_cast<std::size_t>(keep[k])];
    Eigen::RowVector3d pos(q.x, q.y, q.z), n(q.normal_x, q.normal_y, q.normal_z);
    // MLS normals have no sign: point them away from the centroid (a bunch is star-shaped
    // about it to first order).
    if (n.dot(pos) < 0) n = -n;
    s.points.row(static_cast<Eigen::Index>(k)) = pos + centre;
    s.normals.row(static_cast<Eigen::Index>(k)) = n.normalized();
    s.source.push_back(corresponding->indices[static_cast<std::size_t>(keep[k])]);
  }
  return s;
}

const ParamTable<MlsParams>& mls_param_table() {
  static const ParamTable<MlsParams> table =
      ParamTable<MlsParams>()
          .real("radius", "m", &MlsParams::radius, 1e-4, 0.5, "MLS neighbourhood radius (seed 000 gives none)")
          .integer("polynomial_order", "-", &MlsParams::polynomial_order, 0, 4,
                   "order of the local surface (seed 000 Eq. 3: 2)");
  return table;
}

}  // namespace grapebench
