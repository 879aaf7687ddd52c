// Seed 004's CRF (alpha expansion, CGAL): isolated label noise on a grid is removed,
// boundaries between large regions stay, and the post-CRF scores rank like the labels.
#include <gtest/gtest.h>

#include "algorithms/classification/crf_smoothing.h"
#include "synth/rng.h"

namespace grapebench {
namespace {

TEST(CrfSmoothing, RemovesIsolatedLabelNoiseOnAGrid) {
  const int side = 40;
  PointCloud c(side * side, 3);
  Eigen::MatrixXd p(side * side, 3);
  std::vector<int> truth(side * side);
  Rng rng(11);
  int noisy = 0;
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      const int k = i * side + j;
      c.row(k) << 0.01 * i, 0.01 * j, 0;
      truth[k] = j < side / 3 ? 0 : j < 2 * side / 3 ? 1 : 2;  // three bands
      int shown = truth[k];
      if (rng.uniform() < 0.1) shown = (shown + 1 + (rng.uniform() < 0.5)) % 3, ++noisy;  // isolated flips
      p.row(k).setConstant(0.2);
      p(k, shown) = 0.6;
    }
  }
  ASSERT_GT(noisy, 100);
  CrfParams params;
  params.radius = 0.0105;  // the 4-neighbourhood
  params.neighbours = 4;
  // Above ln(0.6 / 0.2) / 1 (a pair of like flips: 3 edges against, 1 for), below
  // ln 3 / 1 at a straight band edge.
  params.weight = 0.8;
  const CrfResult r = crf_smoothing(c, p, params);
  int wrong = 0;
  for (int k = 0; k < side * side; ++k) {
    wrong += r.labels[k] != truth[k];
    Eigen::Index best = 0;
    r.scores.row(k).maxCoeff(&best);
    EXPECT_EQ(best, r.labels[k]) << k;  // the continuous score ranks like the MAP label
    EXPECT_NEAR(r.scores.row(k).sum(), 1, 1e-9);
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_LT(r.energy_after, r.energy_before);
  EXPECT_GE(r.changed, noisy);
  EXPECT_EQ(r.edges, static_cast<std::size_t>(2 * side * (side - 1)));
}

TEST(CrfSmoothing, ZeroWeightKeepsTheClassifiersLabels) {
  PointCloud c(3, 3);
  c << 0, 0, 0, 0.01, 0, 0, 0.02, 0, 0;
  Eigen::MatrixXd p(3, 2);
  p << 0.9, 0.1, 0.2, 0.8, 0.7, 0.3;
  CrfParams params;
  params.weight = 0;
  const CrfResult r = crf_smoothing(c, p, params);
  EXPECT_EQ(r.labels, (std::vector<int>{0, 1, 0}));
  EXPECT_NEAR(r.scores(1, 1), 0.8, 1e-12);
  EXPECT_THROW(crf_smoothing(c, p.topRows(2), params), InputError);
}

}  // namespace
}  // namespace grapebench
