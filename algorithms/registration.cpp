#include "algorithms/registration.h"

#include "algorithms/pcl_cloud.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/features/normal_3d.h>
#include <pcl/registration/icp.h>

#include <Eigen/Eigenvalues>

#include <array>
#include <cmath>

namespace grapebench {

namespace {

pcl::PointCloud<pcl::PointNormal>::Ptr with_normals(const PointCloud& c) {
  const auto xyz = to_pcl(c);
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(xyz);
  ne.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  ne.setKSearch(20);
  pcl::PointCloud<pcl::Normal> normals;
  ne.compute(normals);
  auto out = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  out->resize(xyz->size());
  for (std::size_t i = 0; i < xyz->size(); ++i) {
    auto& p = (*out)[i];
    p.x = (*xyz)[i].x;
    p.y = (*xyz)[i].y;
    p.z = (*xyz)[i].z;
    // Degenerate neighbourhoods give NaN normals: a zero normal drops the point's
    // plane term rather than poisoning the solve.
    const bool ok = std::isfinite(normals[i].normal_x);
    p.normal_x = ok ? normals[i].normal_x : 0.0f;
    p.normal_y = ok ? normals[i].normal_y : 0.0f;
    p.normal_z = ok ? normals[i].normal_z : 0.0f;
    p.curvature = ok ? normals[i].curvature : 0.0f;
  }
  return out;
}

template <class Icp>
IcpResult run_icp(Icp& icp, const IcpParams& p, const Eigen::Isometry3d& initial) {
  icp.setMaxCorrespondenceDistance(p.max_correspondence_distance);
  icp.setMaximumIterations(p.max_iterations);
  icp.setTransformationEpsilon(p.transformation_epsilon);
  icp.setEuclideanFitnessEpsilon(p.fitness_epsilon);
  typename Icp::PointCloudSource aligned;
  icp.align(aligned, initial.matrix());
  IcpResult r;
  r.converged = icp.hasConverged();
  r.transform.matrix() = icp.getFinalTransformation();
  // PCL's fitness counts only pairs closer than the correspondence distance.
  r.fitness = icp.getFitnessScore(p.max_correspondence_distance);
  return r;
}

PointCloud transformed(const PointCloud& c, const Eigen::Isometry3d& t) {
  PointCloud out = (c * t.linear().transpose()).rowwise() + t.translation().transpose();
  return out;
}

void append(PointCloud& to, const PointCloud& c) {
  const Eigen::Index n = to.rows();
  to.conservativeResize(n + c.rows(), 3);
  to.bottomRows(c.rows()) = c;
}

// Principal axes (columns, decreasing variance) and centroid.
void principal_frame(const PointCloud& c, Eigen::Matrix3d& axes, Eigen::Vector3d& centre) {
  centre = c.colwise().mean().transpose();
  const PointCloud d = c.rowwise() - centre.transpose();
  const Eigen::Matrix3d cov = d.transpose() * d / static_cast<double>(c.rows());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  for (int k = 0; k < 3; ++k) axes.col(k) = es.eigenvectors().col(2 - k);
}

}  // namespace

IcpResult icp_align(const PointCloud& source, const PointCloud& target, const Eigen::Isometry3d& initial,
                    const IcpParams& p) {
  require_points(source, 3, "icp source");
  require_points(target, 3, "icp target");
  if (!(p.max_correspondence_distance >= 1e-4 && p.max_correspondence_distance <= 1) || p.max_iterations < 1 ||
      p.max_iterations > 10000) {
    throw InputError("icp: max_correspondence_distance must lie in [1e-4, 1] m and max_iterations in [1, 10000]");
  }
  if (p.point_to_plane) {
    pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal, double> icp;
    icp.setInputSource(with_normals(source));
    icp.setInputTarget(with_normals(target));
    return run_icp(icp, p, initial);
  }
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ, double> icp;
  icp.setInputSource(to_pcl(source));
  icp.setInputTarget(to_pcl(target));
  return run_icp(icp, p, initial);
}

Eigen::Isometry3d pca_alignment(const PointCloud& source, const PointCloud& target) {
  require_points(source, 3, "pca alignment source");
  require_points(target, 3, "pca alignment target");
  Eigen::Matrix3d as, at;
  Eigen::Vector3d cs, ct;
  principal_frame(source, as, cs);
  principal_frame(target, at, ct);
  // Eigenvector signs are arbitrary: of the four proper sign choices take the
  // rotation with the largest trace (smallest angle).
  Eigen::Matrix3d best = Eigen::Matrix3d::Identity();
  double best_trace = -10;
  for (int s = 0; s < 8; ++s) {
    Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
    for (int k = 0; k < 3; ++k) flip(k, k) = (s >> k) & 1 ? -1 : 1;
    const Eigen::Matrix3d r = at * flip * as.transpose();
    if (r.determinant() < 0) continue;
    if (r.trace() > best_trace) {
      best_trace = r.trace();
      best = r;
    }
  }
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = best;
  t.translation() = ct - best * cs;
  return t;
}

RegistrationResult register_seed000(const std::vector<RegistrationView>& views, const IcpParams& icp,
                                    int group_size) {
  if (views.empty()) throw InputError("registration: no views");
  if (group_size < 1) throw InputError("registration: group_size must be at least 1");
  RegistrationResult r;
  r.poses.assign(views.size(), Eigen::Isometry3d::Identity());
  r.icp.assign(views.size(), IcpResult{});
  // Within each group: views onto the group's first view.
  std::vector<std::size_t> heads;
  std::vector<PointCloud> groups;
  for (std::size_t g = 0; g < views.size(); g += static_cast<std::size_t>(group_size)) {
    heads.push_back(g);
    PointCloud merged = views[g].points;
    for (std::size_t k = g + 1; k < std::min(views.size(), g + static_cast<std::size_t>(group_size)); ++k) {
      const IcpResult res = icp_align(views[k].points, merged, pca_alignment(views[k].points, merged), icp);
      r.poses[k] = res.transform;
      r.icp[k] = res;
      append(merged, transformed(views[k].points, res.transform));
    }
    groups.push_back(std::move(merged));
  }
  // Groups onto A1.
  r.merged = groups[0];
  for (std::size_t g = 1; g < groups.size(); ++g) {
    const IcpResult res = icp_align(groups[g], r.merged, pca_alignment(groups[g], r.merged), icp);
    const std::size_t head = heads[g];
    for (std::size_t k = head; k < std::min(views.size(), head + static_cast<std::size_t>(group_size)); ++k) {
      r.poses[k] = res.transform * r.poses[k];
    }
    r.icp[head] = res;
    append(r.merged, transformed(groups[g], res.transform));
  }
  return r;
}

RegistrationResult register_known_angle(const std::vector<RegistrationView>& views, const Eigen::Vector3d& up,
                                        const IcpParams& icp, double bottom_band) {
  if (views.empty()) throw InputError("registration: no views");
  if (!(bottom_band > 0 && bottom_band <= 1)) throw InputError("registration: bottom_band must lie in (0, 1] m");
  RegistrationResult r;
  r.poses.assign(views.size(), Eigen::Isometry3d::Identity());
  r.icp.assign(views.size(), IcpResult{});
  r.merged = views[0].points;
  const Eigen::Vector3d u = up.normalized();
  for (std::size_t k = 1; k < views.size(); ++k) {
    if (views[k].bottom) continue;
    const IcpResult res = icp_align(views[k].points, r.merged, views[k].nominal, icp);
    r.poses[k] = res.transform;
    r.icp[k] = res;
    append(r.merged, transformed(views[k].points, res.transform));
  }
  for (std::size_t k = 1; k < views.size(); ++k) {
    if (!views[k].bottom) continue;
    // Eq. 3: the nominal mounting rotation; Eq. 4: ICP on the lowest band of both clouds.
    const auto band = [&](const PointCloud& c) {
      const Eigen::VectorXd h = c * u;
      const double lo = h.minCoeff();
      std::vector<Eigen::Index> keep;
      for (Eigen::Index i = 0; i < c.rows(); ++i) {
        if (h(i) <= lo + bottom_band) keep.push_back(i);
      }
      PointCloud out(static_cast<Eigen::Index>(keep.size()), 3);
      for (std::size_t i = 0; i < keep.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = c.row(keep[i]);
      return out;
    };
    Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
    start.linear() = views[k].nominal.linear();
    const PointCloud rotated = transformed(views[k].points, start);
    const PointCloud target_band = band(r.merged);
    const PointCloud source_band = band(rotated);
    require_points(source_band, 3, "bottom view band");
    // Centroids of the lowest bands coincide (the bottom view sees the same cap).
    start.translation() = target_band.colwise().mean().transpose() - source_band.colwise().mean().transpose();
    const IcpResult res = icp_align(band(transformed(views[k].points, start)), target_band,
                                    Eigen::Isometry3d::Identity(), icp);
    r.poses[k] = res.transform * start;
    r.icp[k] = res;
    append(r.merged, transformed(views[k].points, r.poses[k]));
  }
  return r;
}

RegistrationResult register_plain_icp(const std::vector<RegistrationView>& views, const IcpParams& icp) {
  if (views.empty()) throw InputError("registration: no views");
  RegistrationResult r;
  r.poses.assign(views.size(), Eigen::Isometry3d::Identity());
  r.icp.assign(views.size(), IcpResult{});
  r.merged = views[0].points;
  for (std::size_t k = 1; k < views.size(); ++k) {
    const IcpResult res = icp_align(views[k].points, r.merged, Eigen::Isometry3d::Identity(), icp);
    r.poses[k] = res.transform;
    r.icp[k] = res;
    append(r.merged, transformed(views[k].points, res.transform));
  }
  return r;
}

double rotation_error_deg(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth) {
  const Eigen::Matrix3d d = estimate.linear().transpose() * truth.linear();
  const double c = std::clamp((d.trace() - 1) / 2, -1.0, 1.0);
  return std::acos(c) * 180 / M_PI;
}

double centroid_displacement(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth,
                             const PointCloud& points) {
  if (points.rows() == 0) return 0;
  const Vec3 c = points.colwise().mean().transpose();
  return (estimate * c - truth * c).norm();
}

const ParamTable<IcpParams>& icp_param_table() {
  using P = IcpParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("max_correspondence_distance", "m", &P::max_correspondence_distance, 1e-4, 1,
                "correspondences farther apart are dropped (seeds 000, 002 give none)")
          .integer("max_iterations", "count", &P::max_iterations, 1, 10000, "ICP iterations")
          .real("transformation_epsilon", "-", &P::transformation_epsilon, 0, 1, "squared transform change to stop")
          .real("fitness_epsilon", "m2", &P::fitness_epsilon, 0, 1, "change of the mean squared error to stop")
          .boolean("point_to_plane", &P::point_to_plane, "point-to-plane error instead of the papers' point-to-point");
  return table;
}

}  // namespace grapebench
