// Seed 004's shape and colour features (Dey et al. 2012, Sect. 3.2.1, after Lalonde et
// al. 2006): per point, the eigenvalues lambda0 >= lambda1 >= lambda2 of the covariance
// of its neighbours within the support radius d give point-ness lambda2, curve-ness
// lambda0 - lambda1 and surface-ness lambda1 - lambda2 (Eq. 2), at one, two or three
// radii, then the point's RGB.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "algorithms/point_cloud.h"
#include "synth/param_table.h"

namespace grapebench {

struct SaliencyParams {
  // Nominal support radius d (Sect. 4.2: "approximately a two inch radius"); the second
  // scale is half of it, the third twice it.
  double radius = 0.05;  // m
  int scales = 2;        // 0 (colour alone), 1, 2 or 3 (Figs. 4-5)
  bool colour = true;    // append R, G, B (0-1)
};
const ParamTable<SaliencyParams>& saliency_param_table();

// The radii in the paper's order: nominal, half, double (m), `scales` of them.
std::vector<double> saliency_radii(const SaliencyParams& p);

struct SaliencyFeatures {
  // N x (3 scales + 3 colour): per radius [lambda2, lambda0 - lambda1, lambda1 - lambda2]
  // in m^2, then R, G, B in [0, 1]. The covariance is divided by the neighbour count
  // (Eq. 1 as printed lacks it, making the eigenvalues grow with point density).
  Eigen::MatrixXd features;
  std::vector<int> neighbours;  // N x scales, row-major: neighbours within each radius (the point included)
};

// Computed in double precision about each query point (no catastrophic cancellation at
// metre offsets). Points with fewer than 3 neighbours at a radius get zeros there.
// Deterministic at any thread count (each point alone). Throws InputError when colours
// are asked for and their count differs from the points', or a coordinate is not finite.
SaliencyFeatures saliency_features(const PointCloud& points, const std::vector<Rgb8>& colours,
                                   const SaliencyParams& p);

// Standardisation of feature columns (zero mean, unit sd; a constant column is left
// centred), fitted on training rows and applied to any rows.
struct FeatureScaling {
  Eigen::RowVectorXd mean, scale;
  Eigen::MatrixXd apply(const Eigen::MatrixXd& x) const;
};
FeatureScaling fit_scaling(const Eigen::MatrixXd& x);

}  // namespace grapebench
