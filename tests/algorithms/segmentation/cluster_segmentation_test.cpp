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

}  // namespace
}  // namespace grapebench
