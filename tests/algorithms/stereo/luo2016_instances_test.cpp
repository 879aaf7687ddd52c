// Seed 001's stages as an instance detector (protocol detection), created through the
// estimator registry, on analytic images whose instances are known exactly: the
// cluster's pixels and each berry's disc (stereo_drawing.h).
#include "algorithms/stereo/luo2016_instances.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "algorithms/registry.h"
#include "algorithms/stereo/stereo_drawing.h"

namespace grapebench {
namespace {

using testing::Colour;

EstimatorBinding bind_instances(const std::string& yaml) {
  nlohmann::ordered_json params;
  return estimator_registry().create(ConfigNode::load_string(yaml, "estimator.yaml"), params);
}

// A detection's mask over the whole image (0 / 1, H x W row-major).
std::vector<std::uint8_t> detection_mask(const ImageDetection& d, int width, int height) {
  std::vector<std::uint8_t> m(static_cast<std::size_t>(width) * height, 0);
  for (int y = 0; y < d.mask_h; ++y)
    for (int x = 0; x < d.mask_w; ++x)
      m[static_cast<std::size_t>(y + d.mask_y) * width + (x + d.mask_x)] =
          d.mask[static_cast<std::size_t>(y) * d.mask_w + x];
  return m;
}

// A disc as the truth: pixels whose centre lies within r of (cx, cy).
std::vector<std::uint8_t> disc_mask(const Circle& c, int width, int height) {
  std::vector<std::uint8_t> m(static_cast<std::size_t>(width) * height, 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      m[static_cast<std::size_t>(y) * width + x] = (x - c.x) * (x - c.x) + (y - c.y) * (y - c.y) <= c.r * c.r;
  return m;
}

double mask_iou(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  std::size_t inter = 0, uni = 0;
  for (std::size_t i = 0; i < a.size(); ++i) inter += a[i] && b[i], uni += a[i] || b[i];
  return uni ? static_cast<double>(inter) / static_cast<double>(uni) : 0;
}

// IoU of a berry detection's mask and a true disc, over the union of their boxes.
double berry_iou(const ImageDetection& d, const Circle& c) {
  const int x0 = std::min(d.mask_x, static_cast<int>(std::floor(c.x - c.r)));
  const int x1 = std::max(d.mask_x + d.mask_w - 1, static_cast<int>(std::ceil(c.x + c.r)));
  const int y0 = std::min(d.mask_y, static_cast<int>(std::floor(c.y - c.r)));
  const int y1 = std::max(d.mask_y + d.mask_h - 1, static_cast<int>(std::ceil(c.y + c.r)));
  if (x1 - x0 + 1 > d.mask_w + 2 * c.r + 2 || y1 - y0 + 1 > d.mask_h + 2 * c.r + 2) return 0;  // apart
  std::size_t inter = 0, uni = 0;
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const bool in_d = x >= d.mask_x && x < d.mask_x + d.mask_w && y >= d.mask_y && y < d.mask_y + d.mask_h &&
                        d.mask[static_cast<std::size_t>(y - d.mask_y) * d.mask_w + (x - d.mask_x)];
      const bool in_c = (x - c.x) * (x - c.x) + (y - c.y) * (y - c.y) <= c.r * c.r;
      inter += in_d && in_c, uni += in_d || in_c;
    }
  }
  return uni ? static_cast<double>(inter) / static_cast<double>(uni) : 0;
}

// Berries matched one to one at COCO's IoU 0.5, greedily in score order as COCOeval.
int matched_berries(const Estimate& e, const std::vector<Circle>& truth) {
  std::vector<bool> taken(truth.size(), false);
  int matched = 0;
  for (const ImageDetection& d : e.instances) {
    if (d.category != "berry") continue;
    int best = -1;
    double best_iou = 0.5;
    for (std::size_t k = 0; k < truth.size(); ++k) {
      const double v = taken[k] ? 0 : berry_iou(d, truth[k]);
      if (v >= best_iou) best_iou = v, best = static_cast<int>(k);
    }
    if (best >= 0) taken[best] = true, ++matched;
  }
  return matched;
}

int count_of(const Estimate& e, const std::string& category) {
  return static_cast<int>(std::count_if(e.instances.begin(), e.instances.end(),
                                        [&](const ImageDetection& d) { return d.category == category; }));
}

// One camera (no right image), the berries' distance given: the cluster is one bunch
// whose mask is the berries' union, and most berries are found at COCO's IoU 0.5.
TEST(Luo2016Instances, OneImageGivesTheClusterAndItsBerries) {
  const testing::AnalyticPair a = testing::analytic_pair();
  const EstimatorBinding bound =
      bind_instances("type: luo2016_instances\ndepth: 0.625\nberries:\n  radius_model: pinhole\n");  // 16 px = 10 mm at 0.625 m
  EXPECT_EQ(bound.input, "image");
  auto pair = std::make_shared<StereoPair>(a.pair);
  pair->right = RgbImage{};
  EstimatorInput in;
  in.stereo = pair;
  const Estimate e = bound.run(in);
  const int w = a.pair.left.width, h = a.pair.left.height;
  ASSERT_EQ(count_of(e, "bunch"), 1) << e.notes;
  const ImageDetection& bunch = e.instances.front();
  EXPECT_EQ(bunch.category, "bunch");
  EXPECT_DOUBLE_EQ(bunch.score, 1);
  EXPECT_TRUE(std::isnan(bunch.volume));  // no stereo pair, no volume
  std::vector<std::uint8_t> berries(static_cast<std::size_t>(w) * h, 0);
  for (const Circle& c : a.circles) {
    const auto m = disc_mask(c, w, h);
    for (std::size_t i = 0; i < m.size(); ++i) berries[i] |= m[i];
  }
  // The region bridges the 1 px gaps between berries (its 3 x 3 dilation): 0.81 measured.
  EXPECT_GE(mask_iou(detection_mask(bunch, w, h), berries), 0.8) << e.notes;
  // Its box is the berries' box, within the 3 x 3 dilation and a pixel of coverage.
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const Circle& c : a.circles)
    x0 = std::min(x0, c.x - c.r), x1 = std::max(x1, c.x + c.r), y0 = std::min(y0, c.y - c.r), y1 = std::max(y1, c.y + c.r);
  EXPECT_NEAR(bunch.x, x0 + 0.5, 2.5);
  EXPECT_NEAR(bunch.y, y0 + 0.5, 2.5);
  EXPECT_NEAR(bunch.x + bunch.w, x1 + 0.5, 2.5);
  EXPECT_NEAR(bunch.y + bunch.h, y1 + 0.5, 2.5);
  const int found = matched_berries(e, a.circles);
  EXPECT_GE(found, 0.8 * static_cast<double>(a.circles.size())) << e.notes;
  EXPECT_LE(count_of(e, "berry") - found, 3) << e.notes;  // few false berries
}

// The stereo pair gives the berries' distance (the cutting point's) and the bunch's
// volume, the full system's on the region.
TEST(Luo2016Instances, TheStereoPairGivesDistanceAndVolume) {
  const testing::AnalyticPair a = testing::analytic_pair();
  EstimatorInput in;
  in.stereo = std::make_shared<StereoPair>(a.pair);
  const Estimate e = bind_instances("type: luo2016_instances\nberries:\n  radius_model: pinhole\n").run(in);
  ASSERT_EQ(count_of(e, "bunch"), 1) << e.notes;
  const ImageDetection& bunch = e.instances.front();
  ASSERT_FALSE(std::isnan(bunch.volume)) << e.notes;
  Luo2016Params system;
  system.berries.radius_model = BerryCircleParams::RadiusModel::Pinhole;
  const Luo2016Result whole = luo2016_stereo(a.pair, system);
  ASSERT_TRUE(whole.ok());
  EXPECT_DOUBLE_EQ(bunch.volume, whole.volume.volume);  // the same region: the same system's answer
  EXPECT_GE(matched_berries(e, a.circles), 0.8 * 25) << e.notes;
}

// Two clusters (10 and 6 berries): the paper's system takes the larger; `regions: all` both, scores their
// shares of the region pixels.
TEST(Luo2016Instances, RegionsLargestOrAll) {
  auto pair = std::make_shared<StereoPair>();
  pair->fx = pair->fy = 1000, pair->cx = 399.5, pair->cy = 299.5;
  pair->left = testing::blank(800, 600, Colour{40, 100, 28});
  testing::draw_foliage(pair->left, 5, 0);
  std::vector<Circle> truth;
  for (const auto& [cx, n] : std::vector<std::pair<double, int>>{{220, 4}, {580, 3}}) {
    for (int row = 0; row < n; ++row)
      for (int k = 0; k < n - row; ++k) {
        const Circle c{cx + (k - 0.5 * (n - row - 1)) * 33, 250 + row * 29.0, 16};
        testing::draw_berry(pair->left, c.x, c.y, c.r, 1.7 * static_cast<double>(truth.size()));
        truth.push_back(c);
      }
  }
  EstimatorInput in;
  in.stereo = pair;
  const Estimate largest = bind_instances("type: luo2016_instances\ndepth: 0.625\nberries: {radius_model: pinhole}\n").run(in);
  ASSERT_EQ(count_of(largest, "bunch"), 1) << largest.notes;
  EXPECT_LT(largest.instances.front().x + largest.instances.front().w, 400);  // the left, 10-berry cluster
  const Estimate all = bind_instances("type: luo2016_instances\ndepth: 0.625\nregions: all\nberries: {radius_model: pinhole}\n").run(in);
  ASSERT_EQ(count_of(all, "bunch"), 2) << all.notes;
  // Scores are the regions' shares: the left, 10-berry cluster's the larger.
  double left = 0, right = 0;
  for (const auto& d : all.instances)
    if (d.category == "bunch") (d.x < 400 ? left : right) = d.score;
  EXPECT_GT(left, 0.55);
  EXPECT_GT(right, 0.2);
  EXPECT_NEAR(left + right, 1, 1e-12);
  const int in_largest = matched_berries(largest, truth), in_all = matched_berries(all, truth);
  EXPECT_GE(in_largest, 8) << largest.notes;
  EXPECT_GE(in_all - in_largest, 4) << all.notes;  // most of the second cluster's 6
}

TEST(Luo2016Instances, WithoutImageOrDistanceIsAnInputError) {
  const EstimatorBinding bound = bind_instances("type: luo2016_instances\n");
  EXPECT_THROW(bound.run(EstimatorInput{}), InputError);
  auto pair = std::make_shared<StereoPair>(testing::analytic_pair().pair);
  pair->right = RgbImage{};  // depth 0 asks the stereo pair for the distance
  EstimatorInput in;
  in.stereo = pair;
  EXPECT_THROW(bound.run(in), InputError);
}

}  // namespace
}  // namespace grapebench
