// Seed 004's spatial smoothing (Dey et al. 2012, Sect. 3.3): a CRF over the points with
// unaries from the classifier's probabilities and a Potts penalty between neighbours
// within a support radius, minimised by alpha expansion (Boykov et al. 2001; CGAL's
// alpha_expansion_graphcut, in place of Delong's gco, which Debian does not package).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "algorithms/point_cloud.h"
#include "synth/param_table.h"

namespace grapebench {

struct CrfParams {
  // Sect. 4.2: the support region of the larger saliency scale (about two inches) for
  // the green set, about one inch for the noisier ripening set.
  double radius = 0.05;  // m
  int neighbours = 8;    // each point joins its nearest this many within the radius
  // Potts weight per edge, in units of the unary -ln p (not stated in the paper).
  double weight = 0.5;
  double min_probability = 1e-4;  // probabilities are clamped here before -ln
};
const ParamTable<CrfParams>& crf_param_table();

struct CrfResult {
  std::vector<int> labels;  // N: the MAP labels
  // N x K continuous post-CRF scores, so that an ROC curve exists: each point's label
  // distribution given its neighbours' MAP labels, p(k) ~ p_svm(k) exp(-w * #neighbours
  // labelled otherwise). Its argmax is the MAP label up to ties and CGAL's stopping
  // tolerance (an expansion optimum is stable against single-point moves).
  Eigen::MatrixXd scores;
  std::size_t edges = 0;
  double energy_before = 0, energy_after = 0;  // of the argmax labels and the MAP labels
  int changed = 0;                              // points whose label the smoothing changed
};

// probabilities: N x K, rows of the points' class probabilities. Throws InputError
// when the sizes differ or a probability is not finite.
CrfResult crf_smoothing(const PointCloud& points, const Eigen::MatrixXd& probabilities, const CrfParams& p);

}  // namespace grapebench
