#include "algorithms/cloud/registration.h"

#include "algorithms/pcl_cloud.h"
#include "algorithms/point_index.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/features/normal_3d.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <limits>

namespace grapebench {

namespace {

// Unit normals of the 20 nearest neighbours' plane (PCL's NormalEstimation, as the
// point-to-plane ICP of PCL had them); a degenerate neighbourhood gets a zero normal,
// which drops its pair's plane term rather than poisoning the solve.
PointCloud plane_normals(const PointCloud& c) {
  const auto xyz = to_pcl(c);
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(xyz);
  ne.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  ne.setKSearch(20);
  pcl::PointCloud<pcl::Normal> normals;
  ne.compute(normals);
  PointCloud out = PointCloud::Zero(c.rows(), 3);
  for (Eigen::Index i = 0; i < c.rows(); ++i) {
    const auto& n = normals[static_cast<std::size_t>(i)];
    if (std::isfinite(n.normal_x) && std::isfinite(n.normal_y) && std::isfinite(n.normal_z))
      out.row(i) = Eigen::RowVector3d(n.normal_x, n.normal_y, n.normal_z);
  }
  return out;
}

// Each source point's nearest target point within `radius` (target index, or -1, and
// squared distance), source points moved by t. Parallel over blocks; each answer
// depends on its point alone, so the result is the same at any thread count.
void correspondences(const PointCloud& source, const PointIndex& target, const Eigen::Isometry3d& t, double radius,
                     std::vector<std::pair<std::int64_t, double>>& out) {
  out.resize(static_cast<std::size_t>(source.rows()));
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, source.rows(), 2048), [&](const tbb::blocked_range<Eigen::Index>& r) {
    for (Eigen::Index i = r.begin(); i < r.end(); ++i)
      out[static_cast<std::size_t>(i)] = target.nearest_within(t * Vec3(source.row(i).transpose()), radius);
  });
}

// The rigid motion minimising the pairs' squared point-to-plane distances, linearised
// in the angles (PCL's TransformationEstimationPointToPlaneLLS; Low 2004): `from`
// moved source points, `to` their target points, `normals` the targets' normals
// (3 x M). Not finite when the normals do not fix the motion.
Eigen::Isometry3d point_to_plane_step(const Eigen::Matrix3Xd& from, const Eigen::Matrix3Xd& to,
                                      const Eigen::Matrix3Xd& normals) {
  Eigen::Matrix<double, 6, 6> ata = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> atb = Eigen::Matrix<double, 6, 1>::Zero();
  for (Eigen::Index k = 0; k < from.cols(); ++k) {
    const Vec3 s = from.col(k), n = normals.col(k);
    Eigen::Matrix<double, 6, 1> row;
    row << s.cross(n), n;
    ata.selfadjointView<Eigen::Lower>().rankUpdate(row);
    atb += row * n.dot(to.col(k) - s);
  }
  const Eigen::Matrix<double, 6, 1> x = ata.selfadjointView<Eigen::Lower>().ldlt().solve(atb);
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  step.linear() = (Eigen::AngleAxisd(x(2), Vec3::UnitZ()) * Eigen::AngleAxisd(x(1), Vec3::UnitY()) *
                   Eigen::AngleAxisd(x(0), Vec3::UnitX()))
                      .toRotationMatrix();
  step.translation() = x.tail<3>();
  return step;
}

// ICP as PCL's IterativeClosestPoint(WithNormals) runs it (the papers' tool), in
// double precision on a nanoflann k-d tree: each iteration pairs every moved source
// point with its nearest target point within the correspondence distance, and the
// rigid motion of least squares over the pairs -- point to point (Umeyama; PCL's
// TransformationEstimationSVD) or, with target normals, point to plane -- is composed
// onto the transform. PCL's DefaultConvergenceCriteria end it: the iteration limit; a
// step rotating by less than acos(0.99999) with a squared translation within
// transformation_epsilon; or the pairs' mean squared distance changing by less than
// fitness_epsilon (absolute) or 1e-5 (relative). Fewer than 3 pairs, or a step the
// pairs do not fix: not converged.
IcpResult icp_loop(const PointCloud& source, const PointCloud& target, const PointCloud& target_normals,
                   const Eigen::Isometry3d& initial, const IcpParams& p) {
  const PointIndex index(target);
  const bool to_plane = target_normals.rows() > 0;
  Eigen::Matrix3Xd normals;
  std::vector<std::pair<std::int64_t, double>> pairs;
  IcpResult r;
  r.transform = initial;
  double previous_mse = std::numeric_limits<double>::max();
  Eigen::Matrix3Xd from, to;
  for (int iteration = 1;; ++iteration) {
    correspondences(source, index, r.transform, p.max_correspondence_distance, pairs);
    Eigen::Index m = 0;
    double sum_d2 = 0;
    for (const auto& [k, d2] : pairs) m += k >= 0, sum_d2 += k >= 0 ? d2 : 0;
    if (m < 3) {
      r.converged = false;
      break;
    }
    from.resize(3, m), to.resize(3, m), normals.resize(3, to_plane ? m : 0);
    m = 0;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      if (pairs[i].first < 0) continue;
      from.col(m) = r.transform * Vec3(source.row(static_cast<Eigen::Index>(i)).transpose());
      if (to_plane) normals.col(m) = target_normals.row(pairs[i].first).transpose();
      to.col(m++) = target.row(pairs[i].first).transpose();
    }
    const Eigen::Isometry3d step =
        to_plane ? point_to_plane_step(from, to, normals) : Eigen::Isometry3d(Eigen::umeyama(from, to, false));
    if (!step.matrix().allFinite()) {
      r.converged = false;
      break;
    }
    r.transform = step * r.transform;
    const double mse = sum_d2 / static_cast<double>(m);
    const double cos_angle = 0.5 * (step.linear().trace() - 1);
    const bool small_step = cos_angle >= 0.99999 && step.translation().squaredNorm() <= p.transformation_epsilon;
    const bool flat_mse = std::abs(mse - previous_mse) < p.fitness_epsilon ||
                          std::abs(mse - previous_mse) / previous_mse < 1e-5;
    previous_mse = mse;
    if (iteration >= p.max_iterations || small_step || flat_mse) {
      r.converged = true;
      break;
    }
  }
  // PCL's fitness score: over the source points with a target point within the
  // correspondence distance after the final transform.
  correspondences(source, index, r.transform, p.max_correspondence_distance, pairs);
  double sum = 0;
  std::size_t n = 0;
  for (const auto& [k, d2] : pairs) n += k >= 0, sum += k >= 0 ? d2 : 0;
  r.fitness = n > 0 ? sum / static_cast<double>(n) : std::numeric_limits<double>::max();
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

// Bro, Acar & Kolda (2008, J. Chemometrics 22:135)'s sign rule for points: each of
// the first two axes towards the side where sum(sign(p) p^2) of the projections p is
// positive; the third their cross product, so the frame is a proper rotation. False
// where a sum is below 1e-6 of sum(|p|^3) (a cloud symmetric about the axis): there
// the sign is not the data's, and the caller falls back to the nearest rule.
bool skew_signs(const PointCloud& c, const Eigen::Vector3d& centre, Eigen::Matrix3d& axes) {
  for (int k = 0; k < 2; ++k) {
    const Eigen::VectorXd p = (c.rowwise() - centre.transpose()) * axes.col(k);
    const double skew = p.dot(p.cwiseAbs());
    if (!(std::abs(skew) > 1e-6 * p.cwiseAbs().array().cube().sum())) return false;
    if (skew < 0) axes.col(k) = -axes.col(k);
  }
  axes.col(2) = axes.col(0).cross(axes.col(1));
  return true;
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
  return icp_loop(source, target, p.point_to_plane ? plane_normals(target) : PointCloud(), initial, p);
}

Eigen::Isometry3d pca_alignment(const PointCloud& source, const PointCloud& target, PcaSign sign) {
  require_points(source, 3, "pca alignment source");
  require_points(target, 3, "pca alignment target");
  Eigen::Matrix3d as, at;
  Eigen::Vector3d cs, ct;
  principal_frame(source, as, cs);
  principal_frame(target, at, ct);
  Eigen::Matrix3d ss = as, st = at;
  if (sign == PcaSign::skew && skew_signs(source, cs, ss) && skew_signs(target, ct, st)) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = st * ss.transpose();
    t.translation() = ct - t.linear() * cs;
    return t;
  }
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
                                    int group_size, PcaSign sign) {
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
      const IcpResult res = icp_align(views[k].points, merged, pca_alignment(views[k].points, merged, sign), icp);
      r.poses[k] = res.transform;
      r.icp[k] = res;
      append(merged, transformed(views[k].points, res.transform));
    }
    groups.push_back(std::move(merged));
  }
  // Groups onto A1.
  r.merged = groups[0];
  for (std::size_t g = 1; g < groups.size(); ++g) {
    const IcpResult res = icp_align(groups[g], r.merged, pca_alignment(groups[g], r.merged, sign), icp);
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
