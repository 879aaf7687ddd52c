// Seed 004's baseline (Dey et al. 2012, Sect. 3.2.2: "the Gaussian Mixture Model
// classifier as used by Lalonde et al." 2006): one Gaussian mixture per class fitted by
// EM on that class's training features (OpenCV's ml::EM), points scored by the
// class posteriors under equal priors.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "synth/param_table.h"

namespace grapebench {

struct GmmParams {
  int components = 3;  // Gaussians per class (Lalonde et al. fit a few per class)
  // full: general covariances; diagonal: axis-aligned (fewer parameters).
  enum class Covariance { Full, Diagonal };
  Covariance covariance = Covariance::Full;
  int max_iterations = 100;
};
const ParamTable<GmmParams>& gmm_param_table();

// One mixture per class, trained on standardised features.
struct GmmClassifier {
  struct Mixture {
    Eigen::VectorXd weights;                // G
    Eigen::MatrixXd means;                  // G x D
    std::vector<Eigen::MatrixXd> inverses;  // G of D x D
    Eigen::VectorXd log_norm;               // G: ln(w_g) - (D ln(2 pi) + ln det S_g) / 2
  };
  std::vector<Mixture> classes;  // K; an absent class has no components
  int dims = 0;
};

// x: M x D; y: M class indices in [0, classes). Deterministic in `seed` (OpenCV's
// k-means start). Throws InputError on sizes that differ or non-finite features.
GmmClassifier train_gmm(const Eigen::MatrixXd& x, const std::vector<int>& y, int classes, const GmmParams& p,
                        std::uint64_t seed);
// N x K posteriors (rows sum to 1), in parallel over rows.
Eigen::MatrixXd gmm_posteriors(const GmmClassifier& model, const Eigen::MatrixXd& x);

}  // namespace grapebench
