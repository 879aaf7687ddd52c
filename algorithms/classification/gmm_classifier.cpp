#include "algorithms/classification/gmm_classifier.h"

#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>
#include <string>

#include "synth/config.h"

namespace grapebench {

const ParamTable<GmmParams>& gmm_param_table() {
  using P = GmmParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .integer("components", "count", &P::components, 1, 20, "Gaussians per class (Lalonde et al. 2006)")
          .choice("covariance", &P::covariance, {{"full", P::Covariance::Full}, {"diagonal", P::Covariance::Diagonal}},
                  "covariance of each Gaussian")
          .integer("max_iterations", "count", &P::max_iterations, 1, 10000, "EM iterations at most");
  return table;
}

GmmClassifier train_gmm(const Eigen::MatrixXd& x, const std::vector<int>& y, int classes, const GmmParams& p,
                        std::uint64_t seed) {
  if (static_cast<std::size_t>(x.rows()) != y.size())
    throw InputError("train_gmm: " + std::to_string(x.rows()) + " feature rows for " + std::to_string(y.size()) +
                     " labels");
  if (!x.allFinite()) throw InputError("train_gmm: a training feature is not finite");
  const auto d = static_cast<int>(x.cols());
  GmmClassifier m;
  m.dims = d;
  m.classes.resize(static_cast<std::size_t>(classes));
  for (int c = 0; c < classes; ++c) {
    std::vector<Eigen::Index> rows;
    for (std::size_t i = 0; i < y.size(); ++i) {
      if (y[i] == c) rows.push_back(static_cast<Eigen::Index>(i));
    }
    const int g = std::min<int>(p.components, static_cast<int>(rows.size()) / std::max(2, d + 1));
    if (g < 1) continue;  // too few points of this class: it scores 0
    cv::Mat samples(static_cast<int>(rows.size()), d, CV_64F);
    for (std::size_t r = 0; r < rows.size(); ++r) {
      for (int k = 0; k < d; ++k) samples.at<double>(static_cast<int>(r), k) = x(rows[r], k);
    }
    cv::Ptr<cv::ml::EM> em = cv::ml::EM::create();
    em->setClustersNumber(g);
    em->setCovarianceMatrixType(p.covariance == GmmParams::Covariance::Full ? cv::ml::EM::COV_MAT_GENERIC
                                                                            : cv::ml::EM::COV_MAT_DIAGONAL);
    em->setTermCriteria(cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, p.max_iterations, 1e-6));
    cv::theRNG().state = seed ^ (0x9e3779b97f4a7c15ULL * static_cast<std::uint64_t>(c + 1));  // k-means start
    if (!em->trainEM(samples)) throw InputError("train_gmm: EM did not converge for class " + std::to_string(c));
    const cv::Mat w = em->getWeights(), means = em->getMeans();
    std::vector<cv::Mat> covs;
    em->getCovs(covs);
    GmmClassifier::Mixture& mix = m.classes[static_cast<std::size_t>(c)];
    mix.weights.resize(g);
    mix.means.resize(g, d);
    mix.log_norm.resize(g);
    for (int k = 0; k < g; ++k) {
      mix.weights[k] = w.at<double>(0, k);
      Eigen::MatrixXd s(d, d);
      for (int a = 0; a < d; ++a) {
        mix.means(k, a) = means.at<double>(k, a);
        for (int b = 0; b < d; ++b) s(a, b) = covs[static_cast<std::size_t>(k)].at<double>(a, b);
      }
      s += 1e-9 * Eigen::MatrixXd::Identity(d, d);  // a degenerate component stays invertible
      const Eigen::LDLT<Eigen::MatrixXd> ldlt(s);
      const double log_det = ldlt.vectorD().array().abs().max(1e-300).log().sum();
      mix.inverses.push_back(ldlt.solve(Eigen::MatrixXd::Identity(d, d)));
      mix.log_norm[k] = std::log(std::max(1e-300, mix.weights[k])) - 0.5 * (d * std::log(2 * M_PI) + log_det);
    }
  }
  return m;
}

Eigen::MatrixXd gmm_posteriors(const GmmClassifier& model, const Eigen::MatrixXd& x) {
  if (x.cols() != model.dims) throw InputError("gmm_posteriors: features of the wrong width");
  const auto k = static_cast<Eigen::Index>(model.classes.size());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(x.rows(), k);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, x.rows(), 256), [&](const tbb::blocked_range<Eigen::Index>& r) {
    Eigen::VectorXd ll(k);
    for (Eigen::Index i = r.begin(); i != r.end(); ++i) {
      const Eigen::VectorXd v = x.row(i).transpose();
      for (Eigen::Index c = 0; c < k; ++c) {
        const GmmClassifier::Mixture& mix = model.classes[static_cast<std::size_t>(c)];
        double best = -std::numeric_limits<double>::infinity(), sum = 0;
        std::vector<double> terms(static_cast<std::size_t>(mix.weights.size()));
        for (Eigen::Index g = 0; g < mix.weights.size(); ++g) {
          const Eigen::VectorXd dv = v - mix.means.row(g).transpose();
          terms[static_cast<std::size_t>(g)] = mix.log_norm[g] - 0.5 * dv.dot(mix.inverses[static_cast<std::size_t>(g)] * dv);
          best = std::max(best, terms[static_cast<std::size_t>(g)]);
        }
        for (double t : terms) sum += std::exp(t - best);
        ll[c] = terms.empty() ? -std::numeric_limits<double>::infinity() : best + std::log(sum);
      }
      const double top = ll.maxCoeff();
      if (!std::isfinite(top)) continue;
      const Eigen::VectorXd e = (ll.array() - top).exp();
      out.row(i) = (e / e.sum()).transpose();
    }
  });
  return out;
}

}  // namespace grapebench
