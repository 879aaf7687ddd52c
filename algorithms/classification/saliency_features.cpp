#include "algorithms/classification/saliency_features.h"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>

#include "algorithms/point_index.h"

namespace grapebench {

const ParamTable<SaliencyParams>& saliency_param_table() {
  using P = SaliencyParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("radius", "m", &P::radius, 0.002, 1,
                "nominal support radius d of Eq. 1 (seed 004 Sect. 4.2: about two inches); scale 2 is d/2, "
                "scale 3 is 2d")
          .integer("scales", "count", &P::scales, 0, 3,
                   "saliency scales (seed 004 Figs. 4-5: 1, 2 or 3; 0 for colour alone)")
          .boolean("colour", &P::colour, "append the point's R, G, B (seed 004 Sect. 3.2.1)")
          .validate([](const P& p, const ConfigNode& n) {
            if (p.scales == 0 && !p.colour) n.fail("scales", "is 0 and colour is false: no feature left");
          });
  return table;
}

std::vector<double> saliency_radii(const SaliencyParams& p) {
  const std::array<double, 3> order{p.radius, 0.5 * p.radius, 2 * p.radius};
  return {order.begin(), order.begin() + std::clamp(p.scales, 0, 3)};
}

namespace {

// Neighbour moments about the query point (offsets d = x - q), per radius.
struct Moments {
  double n = 0;
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  Eigen::Matrix3d ss = Eigen::Matrix3d::Zero();
};

// Eq. 2 from the moments: eigenvalues of the covariance (1/n) sum (x - mean)(x - mean)^T.
Eigen::Vector3d saliency_of(const Moments& m) {
  if (m.n < 3) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d mean = m.s / m.n;
  const Eigen::Matrix3d cov = m.ss / m.n - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d ev = eig.eigenvalues().cwiseMax(0.0);  // ascending: lambda2, lambda1, lambda0
  return {ev[0], ev[2] - ev[1], ev[1] - ev[0]};
}

}  // namespace

SaliencyFeatures saliency_features(const PointCloud& points, const std::vector<Rgb8>& colours,
                                   const SaliencyParams& p) {
  const Eigen::Index n = points.rows();
  if (p.colour && colours.size() != static_cast<std::size_t>(n)) {
    throw InputError("saliency_features: " + std::to_string(colours.size()) + " colours for " + std::to_string(n) +
                     " points");
  }
  if (!points.allFinite()) throw InputError("saliency_features: a point coordinate is not finite");
  const std::vector<double> radii = saliency_radii(p);
  const int scales = static_cast<int>(radii.size());
  SaliencyFeatures out;
  out.features.setZero(n, 3 * scales + (p.colour ? 3 : 0));
  out.neighbours.assign(static_cast<std::size_t>(n * scales), 0);
  if (scales > 0 && n > 0) {
    const double r_max = *std::max_element(radii.begin(), radii.end());
    std::vector<double> r2(radii.size());
    for (std::size_t s = 0; s < radii.size(); ++s) r2[s] = radii[s] * radii[s];
    const PointIndex index(points);
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, 256), [&](const tbb::blocked_range<Eigen::Index>& r) {
      std::array<Moments, 3> m;
      for (Eigen::Index i = r.begin(); i != r.end(); ++i) {
        m = {};
        const Vec3 q = points.row(i).transpose();
        // One search at the largest radius; each point counts at every radius it is within.
        index.for_each_within(q, r_max, [&](std::uint32_t j, double d2) {
          const Eigen::Vector3d d = points.row(j).transpose() - q;
          const Eigen::Matrix3d dd = d * d.transpose();
          for (int s = 0; s < scales; ++s) {
            if (d2 >= r2[static_cast<std::size_t>(s)]) continue;
            m[static_cast<std::size_t>(s)].n += 1;
            m[static_cast<std::size_t>(s)].s += d;
            m[static_cast<std::size_t>(s)].ss += dd;
          }
        });
        for (int s = 0; s < scales; ++s) {
          out.features.block<1, 3>(i, 3 * s) = saliency_of(m[static_cast<std::size_t>(s)]).transpose();
          out.neighbours[static_cast<std::size_t>(i * scales + s)] = static_cast<int>(m[static_cast<std::size_t>(s)].n);
        }
      }
    });
  }
  if (p.colour) {
    for (Eigen::Index i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) out.features(i, 3 * scales + c) = colours[static_cast<std::size_t>(i)][c] / 255.0;
    }
  }
  return out;
}

Eigen::MatrixXd FeatureScaling::apply(const Eigen::MatrixXd& x) const {
  return (x.rowwise() - mean).array().rowwise() / scale.array();
}

FeatureScaling fit_scaling(const Eigen::MatrixXd& x) {
  FeatureScaling s;
  const double n = std::max<double>(1, static_cast<double>(x.rows()));
  s.mean = x.colwise().sum() / n;
  s.scale = ((x.rowwise() - s.mean).array().square().colwise().sum() / n).sqrt();
  for (Eigen::Index c = 0; c < s.scale.size(); ++c) {
    if (!(s.scale[c] > 0)) s.scale[c] = 1;
  }
  return s;
}

}  // namespace grapebench
