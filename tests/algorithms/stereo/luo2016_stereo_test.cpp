// Seed 001's whole system, created through the estimator registry as a scene names
// it, on an analytic stereo pair (stereo_drawing.h's analytic_pair). The cutting point,
// the berries and the bounding volume are known exactly.
#include "algorithms/stereo/luo2016_stereo.h"

#include <gtest/gtest.h>

#include "algorithms/registry.h"
#include "algorithms/stereo/stereo_drawing.h"

namespace grapebench {
namespace {

using testing::Colour;

using testing::AnalyticPair;
using testing::analytic_pair;

TEST(Luo2016Stereo, FindsTheCuttingPointBerriesAndBoundingVolumeOfAnAnalyticPair) {
  const AnalyticPair a = analytic_pair();
  nlohmann::ordered_json params;
  const EstimatorBinding bound = estimator_registry().create(
      ConfigNode::load_string("type: luo2016_stereo\nberries:\n  radius_model: pinhole\n", "estimator.yaml"), params);
  EXPECT_EQ(bound.input, "stereo_pair");
  EstimatorInput in;
  in.stereo = std::make_shared<StereoPair>(a.pair);
  const Estimate e = bound.run(in);
  ASSERT_TRUE(e.error.empty()) << e.error << "\n" << e.notes;

  // The cutting point: on the stalk (an edge line's midpoint), at the stalk's depth.
  ASSERT_EQ(e.points.size(), 1u);
  const Vec3 cut = e.points[0].second;
  const double u = a.pair.fx * cut.x() / cut.z() + a.pair.cx, v = a.pair.fy * cut.y() / cut.z() + a.pair.cy;
  EXPECT_GE(u, a.stalk_x0 - 1.5);
  EXPECT_LE(u, a.stalk_x1 + 1.5);
  EXPECT_GE(v, a.stalk_y0);
  EXPECT_LE(v, a.stalk_y1 + 1);
  EXPECT_NEAR(cut.z(), a.stalk_depth, 0.01 * a.stalk_depth);

  // Berries: most found, each within 2 px of a drawn one (touching discs pull the refit).
  int found = 0;
  for (const Detection& d : e.detections) {
    for (const Circle& c : a.circles) found += std::hypot(d.circle.x - c.x, d.circle.y - c.y) < 2.0;
  }
  EXPECT_GE(found, 0.8 * static_cast<double>(a.circles.size())) << e.notes;

  // The cluster region, answered as one "bunch" instance: it holds every berry's centre.
  ASSERT_EQ(e.instances.size(), 1u);
  const ImageDetection& region = e.instances[0];
  EXPECT_EQ(region.category, "bunch");
  ASSERT_EQ(region.mask.size(), static_cast<std::size_t>(region.mask_w) * region.mask_h);
  for (const Circle& c : a.circles) {
    const int x = static_cast<int>(std::lround(c.x)) - region.mask_x, y = static_cast<int>(std::lround(c.y)) - region.mask_y;
    ASSERT_TRUE(x >= 0 && y >= 0 && x < region.mask_w && y < region.mask_h) << c.x << ", " << c.y;
    EXPECT_EQ(region.mask[static_cast<std::size_t>(y) * region.mask_w + x], 1);
  }

  // Bounding volume: as revolved from the true cutting point and berry centres.
  const Vec3 true_cut((0.5 * (a.stalk_x0 + a.stalk_x1) - a.pair.cx) * a.stalk_depth / a.pair.fx, cut.y(),
                      a.stalk_depth);
  const RevolvedBoundingVolume truth = revolved_bounding_volume(true_cut, a.berries);
  double height = -1, diameter = -1, volume = -1;
  for (const auto& [q, value] : e.values) {
    if (q == Quantity::HangingHeight) height = value;
    if (q == Quantity::MaxDiameter) diameter = value;
    if (q == Quantity::Volume) volume = value;
  }
  EXPECT_NEAR(height, truth.height, 0.003);
  EXPECT_NEAR(diameter, truth.max_diameter, 0.006);  // the cut lies on an edge: up to 4 px off the axis
  EXPECT_NEAR(volume / truth.volume, 1, 0.15);
}

TEST(Luo2016Stereo, WithoutAStereoPairIsAnInputError) {
  EXPECT_THROW(luo2016_estimate(EstimatorInput{}, Luo2016Params{}), InputError);
}

// Degenerate pairs fail with a reason, not a crash inside OpenCV.
TEST(Luo2016Stereo, DegeneratePairsAreInputErrors) {
  const StereoPair good = analytic_pair().pair;
  StereoPair p = good;
  p.right.width = 799;  // sizes differ
  EXPECT_THROW(luo2016_stereo(p, Luo2016Params{}), InputError);
  p = good;
  p.left.data.resize(10);  // not W x H x 3
  EXPECT_THROW(luo2016_stereo(p, Luo2016Params{}), InputError);
  p = good;
  p.left = p.right = RgbImage{4, 4, std::vector<std::uint8_t>(48, 100)};  // smaller than the window
  EXPECT_THROW(luo2016_stereo(p, Luo2016Params{}), InputError);
  p = good;
  p.baseline = 0;
  EXPECT_THROW(luo2016_stereo(p, Luo2016Params{}), InputError);
  p = good;
  p.fx = std::nan("");
  EXPECT_THROW(luo2016_stereo(p, Luo2016Params{}), InputError);
  ClusterRegion other;  // a caller's region of another image size
  other.width = other.height = 10, other.mask.assign(100, 255), other.area = 100, other.x1 = other.y1 = 9;
  EXPECT_THROW(luo2016_stereo(good, Luo2016Params{}, &other), InputError);
}

TEST(Luo2016Stereo, FailuresNameTheirStage) {
  const AnalyticPair a = analytic_pair();
  StereoPair flat = a.pair;
  std::fill(flat.left.data.begin(), flat.left.data.end(), 90);
  EXPECT_EQ(luo2016_stereo(flat, Luo2016Params{}).failure, "no cluster region");
  Luo2016Params far;
  far.matching.depth_min = 1.0;  // the stalk (0.625 m) lies outside the searched disparities
  far.berries.radius_model = BerryCircleParams::RadiusModel::Pinhole;
  EXPECT_NE(luo2016_stereo(a.pair, far).failure.find("cutting point not matched"), std::string::npos);
}

// The protocol's oracle ablation (input.oracle): a given cluster mask replaces the
// segmentation (holes filled, as the paper's region), a given image the one the berry
// stage reads; nothing else changes.
TEST(Luo2016Stereo, AnOracleReplacesTheSegmentationAndTheBerryStagesImage) {
  const AnalyticPair a = analytic_pair();
  const int w = a.pair.left.width, h = a.pair.left.height;
  EstimatorInput in;
  in.stereo = std::make_shared<StereoPair>(a.pair);
  Luo2016Params p;
  p.berries.radius_model = BerryCircleParams::RadiusModel::Pinhole;
  const ClusterRegion own = segment_cluster(a.pair.left, p.segmentation);
  ASSERT_TRUE(own.found());

  // The given region: the segmented one without its bottom 20 rows, a 5 x 5 hole
  // punched at its barycentre.
  auto oracle = std::make_shared<StereoOracle>();
  oracle->cluster.assign(static_cast<std::size_t>(w) * h, 0);
  for (int y = own.y0; y <= own.y1 - 20; ++y)
    for (int x = own.x0; x <= own.x1; ++x)
      oracle->cluster[static_cast<std::size_t>(y) * w + x] = own.mask[static_cast<std::size_t>(y) * w + x] ? 1 : 0;
  for (int y = -2; y <= 2; ++y)
    for (int x = -2; x <= 2; ++x)
      oracle->cluster[static_cast<std::size_t>(std::lround(own.yc) + y) * w + std::lround(own.xc) + x] = 0;
  in.oracle = oracle;
  Estimate e = luo2016_estimate(in, p);
  ASSERT_EQ(e.instances.size(), 1u);
  const ImageDetection& region = e.instances[0];
  EXPECT_EQ(region.mask_y, own.y0);
  EXPECT_EQ(region.mask_y + region.mask_h - 1, own.y1 - 20);
  for (int y = 0; y < region.mask_h; ++y)
    for (int x = 0; x < region.mask_w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y + region.mask_y) * w + (x + region.mask_x);
      ASSERT_EQ(region.mask[static_cast<std::size_t>(y) * region.mask_w + x], own.mask[i] ? 1 : 0) << x << ", " << y;
    }
  ASSERT_EQ(e.points.size(), 1u) << e.error;  // the cut stands on the given region's top

  // The berry stage's image: all black finds nothing; the berries drawn as white discs
  // with black outlines (as the protocol draws them from the labels) finds them.
  oracle = std::make_shared<StereoOracle>();
  oracle->berry_edges.width = w, oracle->berry_edges.height = h;
  oracle->berry_edges.data.assign(static_cast<std::size_t>(w) * h * 3, 0);
  in.oracle = oracle;
  e = luo2016_estimate(in, p);
  EXPECT_TRUE(e.detections.empty());
  std::vector<int> ids(static_cast<std::size_t>(w) * h, -1);  // the first disc over each pixel
  for (std::size_t k = a.circles.size(); k-- > 0;) {
    const Circle& c = a.circles[k];
    for (int y = std::max(0, int(c.y - c.r) - 1); y <= std::min(h - 1, int(c.y + c.r) + 1); ++y)
      for (int x = std::max(0, int(c.x - c.r) - 1); x <= std::min(w - 1, int(c.x + c.r) + 1); ++x)
        if (std::hypot(x - c.x, y - c.y) <= c.r) ids[static_cast<std::size_t>(y) * w + x] = static_cast<int>(k);
  }
  const auto id = [&](int x, int y) { return ids[static_cast<std::size_t>(y) * w + x]; };
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      const int k = id(x, y);
      if (k >= 0 && id(x - 1, y) == k && id(x + 1, y) == k && id(x, y - 1) == k && id(x, y + 1) == k)
        std::fill_n(oracle->berry_edges.data.begin() + 3 * (static_cast<std::size_t>(y) * w + x), 3, 255);
    }
  e = luo2016_estimate(in, p);
  int found = 0;
  for (const Detection& d : e.detections)
    for (const Circle& c : a.circles) found += std::hypot(d.circle.x - c.x, d.circle.y - c.y) < 2.0;
  EXPECT_GE(found, 0.8 * static_cast<double>(a.circles.size())) << e.notes;

  oracle->berry_edges.width = w - 1;  // of another size: an input error naming it
  EXPECT_THROW(luo2016_estimate(in, p), InputError);
  oracle = std::make_shared<StereoOracle>();
  oracle->cluster.assign(static_cast<std::size_t>(w) * h - 1, 0);  // one value short
  in.oracle = oracle;
  EXPECT_THROW(luo2016_estimate(in, p), InputError);
}

}  // namespace
}  // namespace grapebench
