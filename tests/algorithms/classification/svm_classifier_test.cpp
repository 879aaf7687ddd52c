// Seed 004's classifiers on toy sets: the SVM (LIBSVM) and the GMM baseline separate
// separable classes, give probabilities, and are the same on a rerun.
#include <gtest/gtest.h>

#include "algorithms/classification/gmm_classifier.h"
#include "algorithms/classification/svm_classifier.h"
#include "synth/rng.h"

namespace grapebench {
namespace {

// Three Gaussian blobs in 2D, far apart: a separable toy set.
void blobs(int per_class, std::uint64_t seed, Eigen::MatrixXd& x, std::vector<int>& y) {
  const double centre[3][2] = {{-3, 0}, {3, 0}, {0, 4}};
  Rng rng(seed);
  x.resize(3 * per_class, 2);
  y.clear();
  for (int c = 0; c < 3; ++c) {
    for (int i = 0; i < per_class; ++i) {
      x.row(c * per_class + i) << centre[c][0] + 0.5 * rng.normal(), centre[c][1] + 0.5 * rng.normal();
      y.push_back(c);
    }
  }
}

int argmax(const Eigen::MatrixXd& p, Eigen::Index i) {
  Eigen::Index k = 0;
  p.row(i).maxCoeff(&k);
  return static_cast<int>(k);
}

TEST(SvmClassifier, SeparatesASeparableSet) {
  Eigen::MatrixXd x, xt;
  std::vector<int> y, yt;
  blobs(100, 1, x, y);
  blobs(200, 2, xt, yt);
  const SvmModel m = train_svm(x, y, 3, SvmParams{}, 5);
  EXPECT_GT(m.support_vectors(), 0);
  const Eigen::MatrixXd p = svm_probabilities(m, xt);
  int correct = 0;
  for (Eigen::Index i = 0; i < xt.rows(); ++i) {
    correct += argmax(p, i) == yt[static_cast<std::size_t>(i)];
    EXPECT_NEAR(p.row(i).sum(), 1, 1e-9);
  }
  EXPECT_EQ(correct, xt.rows());
  // Retrained with the same seed: the same probabilities (LIBSVM's rand() is seeded).
  const Eigen::MatrixXd again = svm_probabilities(train_svm(x, y, 3, SvmParams{}, 5), xt);
  EXPECT_EQ((again - p).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SvmClassifier, AbsentClassScoresZeroAndBadInputIsRefused) {
  Eigen::MatrixXd x, xt;
  std::vector<int> y, yt;
  blobs(50, 3, x, y);
  const Eigen::MatrixXd two = x.topRows(100);
  const std::vector<int> y2(y.begin(), y.begin() + 100);
  const SvmModel m = train_svm(two, y2, 3, SvmParams{}, 1);
  const Eigen::MatrixXd p = svm_probabilities(m, x);
  EXPECT_EQ(p.col(2).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_THROW(train_svm(x.topRows(50), std::vector<int>(50, 0), 3, SvmParams{}, 1), InputError);
  EXPECT_THROW(train_svm(x, y2, 3, SvmParams{}, 1), InputError);
  EXPECT_THROW(svm_probabilities(m, Eigen::MatrixXd::Zero(2, 5)), InputError);
}

TEST(GmmClassifier, SeparatesASeparableSet) {
  Eigen::MatrixXd x, xt;
  std::vector<int> y, yt;
  blobs(200, 4, x, y);
  blobs(200, 5, xt, yt);
  GmmParams p;
  p.components = 2;
  const GmmClassifier m = train_gmm(x, y, 3, p, 9);
  const Eigen::MatrixXd post = gmm_posteriors(m, xt);
  int correct = 0;
  for (Eigen::Index i = 0; i < xt.rows(); ++i) correct += argmax(post, i) == yt[static_cast<std::size_t>(i)];
  EXPECT_EQ(correct, xt.rows());
  const Eigen::MatrixXd again = gmm_posteriors(train_gmm(x, y, 3, p, 9), xt);
  EXPECT_EQ((again - post).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace grapebench
