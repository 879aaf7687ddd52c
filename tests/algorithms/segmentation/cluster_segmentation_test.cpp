#include "algorithms/segmentation/cluster_segmentation.h"

#include <gtest/gtest.h>

#include "algorithms/stereo/stereo_drawing.h"

namespace grapebench {
namespace {

using testing::Colour;

// A disc of black grapes on foliage: Otsu on H - I separates it, the holes of its
// highlights are filled, and the barycentre, top point and L_max are the disc's.
TEST(ClusterSegmentation, ABlackClusterOnFoliageIsItsRegion) {
  RgbImage im = testing::blank(400, 300, Colour{40, 110, 30});
  testing::draw_foliage(im, 3, 0);
  const double cx = 210, cy = 160, R = 60;
  for (int y = 0; y < 300; ++y) {
    for (int x = 0; x < 400; ++x) {
      testing::blend(im, x, y, Colour{60, 30, 70},
                     testing::coverage(x, y, [&](double u, double v) { return std::hypot(u - cx, v - cy) < R; }));
    }
  }
  testing::draw_berry(im, cx, cy, 20);  // a highlight inside: no hole in the region
  const ClusterRegion r = segment_cluster(im, ClusterSegmentationParams{});
  ASSERT_TRUE(r.found());
  EXPECT_NEAR(r.xc, cx, 1.0);
  EXPECT_NEAR(r.yc, cy, 1.0);
  EXPECT_NEAR(r.yt, cy - R, 3.0);  // two dilations of 1 px
  EXPECT_NEAR(r.xt, cx, 3.0);
  EXPECT_NEAR(r.l_max, 2 * R, 5.0);
  EXPECT_NEAR(r.area, M_PI * (R + 2) * (R + 2), 0.03 * M_PI * R * R);  // grown 1 px by each dilation
}

// Red grapes on Cr; nothing grape-coloured: no region.
TEST(ClusterSegmentation, RedOnCrAndNothingWithoutAGrape) {
  RgbImage im = testing::blank(300, 200, Colour{40, 110, 30});
  testing::draw_foliage(im, 5, 0);
  for (int y = 0; y < 200; ++y) {
    for (int x = 0; x < 300; ++x) {
      testing::blend(im, x, y, Colour{170, 40, 50},
                     testing::coverage(x, y, [&](double u, double v) { return std::hypot(u - 150, v - 100) < 40; }));
    }
  }
  ClusterSegmentationParams p;
  p.component = ClusterSegmentationParams::Component::Cr;
  const ClusterRegion r = segment_cluster(im, p);
  ASSERT_TRUE(r.found());
  EXPECT_NEAR(r.xc, 150, 1.0);
  EXPECT_NEAR(r.yc, 100, 1.0);
  const RgbImage plain = testing::blank(300, 200, Colour{40, 110, 30});
  EXPECT_FALSE(segment_cluster(plain, p).found());
}

// H - I through the approximate acos (with std::acos near a rounding boundary) is the
// same level as Gonzalez & Woods' formula with std::acos, for every 8-bit colour.
TEST(ClusterSegmentation, HueMinusIntensityIsTheExactFormulasForEveryColour) {
  RgbImage im;
  im.width = 4096, im.height = 4096;
  im.data.resize(3u << 24);
  for (std::uint32_t c = 0; c < (1u << 24); ++c)
    im.data[3 * c] = c >> 16, im.data[3 * c + 1] = (c >> 8) & 255, im.data[3 * c + 2] = c & 255;
  const std::vector<std::uint8_t> got = cluster_component(im, ClusterSegmentationParams::Component::HueMinusIntensity);
  ASSERT_EQ(got.size(), 1u << 24);
  std::size_t wrong = 0, first = 0;
  for (std::uint32_t c = 0; c < (1u << 24); ++c) {
    const double r = (c >> 16) / 255.0, g = ((c >> 8) & 255) / 255.0, b = (c & 255) / 255.0;
    const double num = 0.5 * ((r - g) + (r - b));
    const double den = std::sqrt((r - g) * (r - g) + (r - b) * (g - b));
    double h = 0;
    if (den > 1e-12) {
      const double theta = std::acos(std::clamp(num / den, -1.0, 1.0));
      h = (b > g ? 2 * M_PI - theta : theta) / (2 * M_PI);
    }
    const auto want = static_cast<std::uint8_t>(std::lround((h - (r + g + b) / 3.0 + 1.0) * 127.5));
    if (got[c] != want && wrong++ == 0) first = c;
  }
  EXPECT_EQ(wrong, 0u) << "first at colour 0x" << std::hex << first;
}

}  // namespace
}  // namespace grapebench
