// Seed 004's classifier through the registry on analytic shapes with known classes:
// balls (berries), thin cylinders (branches) and flat discs (leaves), trained on one
// copy and scored on another, shape alone and before and after the CRF.
#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/classification/dey2012_classification.h"
#include "algorithms/registry.h"
#include "synth/rng.h"

namespace grapebench {
namespace {

// Shapes sampled on their surfaces around x0: 6 balls of 1 cm, 4 rods of 3 mm x 20 cm,
// 4 discs of 6 cm; classes 0, 1, 2. Colours all alike (shape must decide).
void add_shapes(double x0, std::uint64_t seed, std::vector<Vec3>& pts, std::vector<int>& cls) {
  Rng rng(seed);
  auto unit = [&] {
    Vec3 v;
    do v = Vec3(rng.normal(), rng.normal(), rng.normal());
    while (v.norm() < 1e-9);
    return v.normalized();
  };
  for (int b = 0; b < 6; ++b) {
    const Vec3 c(x0 + 0.1 * (b % 3), 0.0, 0.1 * (b / 3));
    for (int i = 0; i < 400; ++i) pts.push_back(c + 0.01 * unit()), cls.push_back(0);
  }
  for (int r = 0; r < 4; ++r) {
    const Vec3 a(x0 + 0.08 * r, 0.2, 0), axis = Vec3(0.2, 0.3, 1).normalized();
    const Vec3 u = axis.unitOrthogonal(), w = axis.cross(u);
    for (int i = 0; i < 600; ++i) {
      const double t = rng.uniform(0, 0.2), phi = rng.uniform(0, 2 * M_PI);
      pts.push_back(a + t * axis + 0.003 * (std::cos(phi) * u + std::sin(phi) * w)), cls.push_back(1);
    }
  }
  for (int d = 0; d < 4; ++d) {
    const Vec3 c(x0 + 0.15 * d, 0.45, 0), n = Vec3(0.1 * d, 1, 0.3).normalized();
    const Vec3 u = n.unitOrthogonal(), w = n.cross(u);
    for (int i = 0; i < 800; ++i) {
      const double r = 0.06 * std::sqrt(rng.uniform()), phi = rng.uniform(0, 2 * M_PI);
      pts.push_back(c + r * (std::cos(phi) * u + std::sin(phi) * w)), cls.push_back(2);
    }
  }
}

struct LabelledCase {
  EstimatorInput input;
  std::vector<int> truth;
};

LabelledCase analytic_case() {
  std::vector<Vec3> pts;
  std::vector<int> cls;
  add_shapes(-1.0, 1, pts, cls);
  const std::size_t train = pts.size();
  add_shapes(1.0, 2, pts, cls);
  LabelledCase c;
  c.input.points = to_point_cloud(pts);
  c.input.colours.assign(pts.size(), Rgb8{90, 140, 60});
  c.input.classes = {"berry", "branch", "leaf"};
  c.truth = cls;
  c.input.train_labels = cls;
  for (std::size_t i = train; i < pts.size(); ++i) c.input.train_labels[i] = -1;
  return c;
}

double test_accuracy(const LabelledCase& c, const Eigen::MatrixXd& scores) {
  int right = 0, n = 0;
  for (std::size_t i = 0; i < c.truth.size(); ++i) {
    if (c.input.train_labels[i] >= 0) continue;
    Eigen::Index k = 0;
    scores.row(static_cast<Eigen::Index>(i)).maxCoeff(&k);
    right += k == c.truth[i], ++n;
  }
  return static_cast<double>(right) / n;
}

struct Variant {
  const char* name;
  const char* yaml;
};
class Dey2012Shapes : public ::testing::TestWithParam<Variant> {};

TEST_P(Dey2012Shapes, ClassifiesBallsRodsAndDiscsByShape) {
  const LabelledCase c = analytic_case();
  nlohmann::ordered_json params;
  const EstimatorBinding e = estimator_registry().create(ConfigNode::load_string(GetParam().yaml, "t.yaml"), params);
  EXPECT_EQ(e.input, "labelled_cloud");
  const Estimate est = e.run(c.input);
  ASSERT_EQ(est.class_scores.rows(), c.input.points.rows());
  EXPECT_GT(test_accuracy(c, est.class_scores), 0.97) << GetParam().yaml;
  // Training rows carry their one-hot label.
  EXPECT_EQ(est.class_scores(0, c.truth[0]), 1.0);
}

INSTANTIATE_TEST_SUITE_P(
    Variants, Dey2012Shapes,
    ::testing::Values(
        Variant{"svm_one_scale", "type: dey2012_classification\nfeatures: {radius: 0.02, scales: 1, colour: false}\ncrf: false"},
        Variant{"svm_two_scales_rgb_crf",
                "type: dey2012_classification\nfeatures: {radius: 0.02, scales: 2, colour: true}\nsmoothing: {radius: 0.01}"},
        Variant{"gmm_two_scales", "type: dey2012_classification\nfeatures: {radius: 0.02, scales: 2, colour: false}\n"
                                  "classifier: gmm\ncrf: false"}),
    [](const ::testing::TestParamInfo<Variant>& i) { return std::string(i.param.name); });

TEST(Dey2012Classification, RefusesInputWithoutTrainingLabels) {
  LabelledCase c = analytic_case();
  Dey2012Params p;
  c.input.train_labels.clear();
  EXPECT_THROW(dey2012_estimate(c.input, p), InputError);
  c = analytic_case();
  std::fill(c.input.train_labels.begin(), c.input.train_labels.end(), 0);
  EXPECT_THROW(dey2012_estimate(c.input, p), InputError);  // nothing to classify
}

}  // namespace
}  // namespace grapebench
