#include "algorithms/classification/dey2012_classification.h"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <random>
#include <sstream>

#include "synth/rng.h"

namespace grapebench {

const ParamTable<Dey2012Params>& dey2012_param_table() {
  using P = Dey2012Params;
  static const ParamTable<P> table =
      ParamTable<P>()
          .section("features", &P::features, saliency_param_table(),
                   "saliency at 1-3 scales and colour (seed 004 Sect. 3.2.1, Eqs. 1-2)")
          .choice("classifier", &P::classifier, {{"svm", P::Classifier::Svm}, {"gmm", P::Classifier::Gmm}},
                  "LIBSVM's RBF C-SVC (seed 004 Sect. 3.2.2) or Lalonde's GMM baseline")
          .section("svm", &P::svm, svm_param_table(), "the SVM (seed 004 Sect. 4.2)")
          .when("classifier: svm", [](const P& p) { return p.classifier == P::Classifier::Svm; })
          .section("gmm", &P::gmm, gmm_param_table(), "the GMM baseline (Lalonde et al. 2006)")
          .when("classifier: gmm", [](const P& p) { return p.classifier == P::Classifier::Gmm; })
          .integer("train_per_class", "count", &P::train_per_class, 10, 100000,
                   "training points drawn per class, equal numbers (seed 004 Sect. 4.2)")
          .boolean("crf", &P::crf, "smooth the labels with the CRF (seed 004 Sect. 3.3, Figs. 6-7)")
          .section("smoothing", &P::smoothing, crf_param_table(), "the CRF's Potts term (seed 004 Sect. 3.3)")
          .when("crf: true", [](const P& p) { return p.crf; })
          .seed("seed", &P::seed, "training draw, LIBSVM's probability folds and EM's start");
  return table;
}

namespace {

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Equal numbers per class (at most `per_class`, fewer where the part has fewer), drawn
// without replacement from the training points in a seeded order.
std::vector<Eigen::Index> training_draw(const std::vector<int>& labels, int classes, int per_class,
                                        std::uint64_t seed) {
  std::vector<std::vector<Eigen::Index>> by_class(static_cast<std::size_t>(classes));
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] >= 0) by_class[static_cast<std::size_t>(labels[i])].push_back(static_cast<Eigen::Index>(i));
  }
  std::vector<Eigen::Index> out;
  Rng rng(derive_seed(seed, 0x7a1));
  for (auto& rows : by_class) {
    // Partial Fisher-Yates: the first `per_class` of a seeded shuffle.
    const std::size_t take = std::min(rows.size(), static_cast<std::size_t>(per_class));
    for (std::size_t i = 0; i < take; ++i) {
      const auto j = i + static_cast<std::size_t>(rng.uniform() * static_cast<double>(rows.size() - i));
      std::swap(rows[i], rows[std::min(j, rows.size() - 1)]);
    }
    out.insert(out.end(), rows.begin(), rows.begin() + static_cast<std::ptrdiff_t>(take));
  }
  return out;
}

}  // namespace

Dey2012Result dey2012_classify(const PointCloud& points, const std::vector<Rgb8>& colours,
                               const std::vector<int>& train_labels, int classes, const Dey2012Params& p) {
  const auto n = static_cast<std::size_t>(points.rows());
  if (train_labels.size() != n)
    throw InputError("dey2012: " + std::to_string(train_labels.size()) + " training labels for " + std::to_string(n) +
                     " points");
  if (classes < 2) throw InputError("dey2012: needs at least two classes");
  std::vector<Eigen::Index> test;
  for (std::size_t i = 0; i < n; ++i) {
    if (train_labels[i] >= classes) throw InputError("dey2012: training label outside [0, classes)");
    if (train_labels[i] < 0) test.push_back(static_cast<Eigen::Index>(i));
  }
  if (test.empty()) throw InputError("dey2012: no point to classify (every point has a training label)");

  Dey2012Result r;
  auto t0 = std::chrono::steady_clock::now();
  const SaliencyFeatures f = saliency_features(points, colours, p.features);
  r.seconds_features = since(t0);

  t0 = std::chrono::steady_clock::now();
  const std::vector<Eigen::Index> train = training_draw(train_labels, classes, p.train_per_class, p.seed);
  r.train_points = static_cast<int>(train.size());
  Eigen::MatrixXd x_train(static_cast<Eigen::Index>(train.size()), f.features.cols());
  std::vector<int> y_train(train.size());
  for (std::size_t i = 0; i < train.size(); ++i) {
    x_train.row(static_cast<Eigen::Index>(i)) = f.features.row(train[i]);
    y_train[i] = train_labels[static_cast<std::size_t>(train[i])];
  }
  const FeatureScaling scaling = fit_scaling(x_train);
  x_train = scaling.apply(x_train);
  Eigen::MatrixXd x_test(static_cast<Eigen::Index>(test.size()), f.features.cols());
  for (std::size_t i = 0; i < test.size(); ++i) x_test.row(static_cast<Eigen::Index>(i)) = f.features.row(test[i]);
  x_test = scaling.apply(x_test);

  Eigen::MatrixXd prob;
  if (p.classifier == Dey2012Params::Classifier::Svm) {
    const SvmModel model = train_svm(x_train, y_train, classes, p.svm, p.seed);
    r.seconds_train = since(t0);
    r.support_vectors = model.support_vectors();
    t0 = std::chrono::steady_clock::now();
    prob = svm_probabilities(model, x_test);
  } else {
    const GmmClassifier model = train_gmm(x_train, y_train, classes, p.gmm, p.seed);
    r.seconds_train = since(t0);
    t0 = std::chrono::steady_clock::now();
    prob = gmm_posteriors(model, x_test);
  }
  r.seconds_predict = since(t0);
  r.scored_points = static_cast<int>(test.size());

  Eigen::MatrixXd test_scores = prob;
  if (p.crf) {
    t0 = std::chrono::steady_clock::now();
    PointCloud test_points(static_cast<Eigen::Index>(test.size()), 3);
    for (std::size_t i = 0; i < test.size(); ++i) test_points.row(static_cast<Eigen::Index>(i)) = points.row(test[i]);
    r.crf = crf_smoothing(test_points, prob, p.smoothing);
    test_scores = r.crf.scores;
    r.seconds_crf = since(t0);
  }
  r.probabilities = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), classes);
  for (std::size_t i = 0; i < n; ++i) {
    if (train_labels[i] >= 0) r.probabilities(static_cast<Eigen::Index>(i), train_labels[i]) = 1;
  }
  r.scores = r.probabilities;
  for (std::size_t i = 0; i < test.size(); ++i) {
    r.probabilities.row(test[i]) = prob.row(static_cast<Eigen::Index>(i));
    r.scores.row(test[i]) = test_scores.row(static_cast<Eigen::Index>(i));
  }
  return r;
}

Estimate dey2012_estimate(const EstimatorInput& input, const Dey2012Params& p) {
  if (input.classes.empty() || input.train_labels.empty())
    throw InputError("dey2012: the input has no classes or training labels (protocol classification gives them)");
  const Dey2012Result r =
      dey2012_classify(input.points, input.colours, input.train_labels, static_cast<int>(input.classes.size()), p);
  Estimate e;
  e.class_scores = r.scores;
  std::ostringstream notes;
  notes << "train_points=" << r.train_points << " scored_points=" << r.scored_points;
  if (p.classifier == Dey2012Params::Classifier::Svm) notes << " support_vectors=" << r.support_vectors;
  if (p.crf) notes << " crf_edges=" << r.crf.edges << " crf_changed=" << r.crf.changed;
  e.notes = notes.str();
  return e;
}

}  // namespace grapebench
