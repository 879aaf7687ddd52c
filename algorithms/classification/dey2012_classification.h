// Seed 004's classifier (Dey et al. 2012, Sect. 3.2-3.3): saliency and colour features
// per point (saliency_features), a multi-class SVM with probabilities trained on equal
// numbers of labelled points per class (svm_classifier; or Lalonde's GMM baseline,
// gmm_classifier), then CRF smoothing (crf_smoothing).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "algorithms/classification/crf_smoothing.h"
#include "algorithms/estimate.h"
#include "algorithms/classification/gmm_classifier.h"
#include "algorithms/classification/saliency_features.h"
#include "algorithms/classification/svm_classifier.h"

namespace grapebench {

struct Dey2012Params {
  SaliencyParams features;
  enum class Classifier { Svm, Gmm };
  Classifier classifier = Classifier::Svm;
  SvmParams svm;
  GmmParams gmm;
  // Training points drawn per class (equal numbers, Sect. 4.2; the paper used about
  // 29k per class: LIBSVM's training time grows about quadratically with it).
  int train_per_class = 1500;
  bool crf = true;  // Figs. 6-7: after the CRF; false: the classifier's own scores (Figs. 4-5)
  CrfParams smoothing;
  std::uint64_t seed = 2012;  // training draw, LIBSVM's probability folds, EM's start
};
const ParamTable<Dey2012Params>& dey2012_param_table();

struct Dey2012Result {
  // N x K: classifier probabilities, and the scores handed on (after the CRF when it
  // runs). Rows of training points hold their one-hot training label.
  Eigen::MatrixXd probabilities, scores;
  int train_points = 0;     // drawn for training (equal per class where the part has them)
  int scored_points = 0;    // points with label -1: classified and smoothed
  int support_vectors = 0;  // SVM only
  CrfResult crf;
  double seconds_features = 0, seconds_train = 0, seconds_predict = 0, seconds_crf = 0;
};

// points N x 3 (m), colours N, train_labels N (class index, or -1 where to classify),
// classes K >= 2. Throws InputError on sizes that differ, no point to classify or a
// training part with fewer than two classes.
Dey2012Result dey2012_classify(const PointCloud& points, const std::vector<Rgb8>& colours,
                               const std::vector<int>& train_labels, int classes, const Dey2012Params& p);

// As an estimator: Estimate::class_scores (N x K) from the input's points, colours,
// classes and training labels; the notes carry the counts and stage times.
Estimate dey2012_estimate(const EstimatorInput& input, const Dey2012Params& p);

}  // namespace grapebench
