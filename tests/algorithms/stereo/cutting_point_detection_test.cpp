#include "algorithms/stereo/cutting_point_detection.h"

#include <gtest/gtest.h>

#include "algorithms/stereo/stereo_drawing.h"

namespace grapebench {
namespace {

using testing::Colour;

std::vector<std::uint8_t> grey_of(const RgbImage& im) {
  std::vector<std::uint8_t> g(static_cast<std::size_t>(im.width) * im.height);
  for (std::size_t i = 0; i < g.size(); ++i) g[i] = im.data[3 * i + 1];
  return g;
}

// A straight edge between two grey levels, through (x0, y0) at `deg` from the x axis,
// drawn with exact coverage: the Hough step finds a segment on it within 1 px.
TEST(CuttingPointDetection, HoughFindsARenderedStraightEdgeWithinOnePixel) {
  for (const double deg : {90.0, 80.0, 63.0, 105.0}) {
    const double x0 = 40.3, y0 = 30.0, a = deg * M_PI / 180;
    const double nx = -std::sin(a), ny = std::cos(a);  // normal of the edge
    RgbImage im = testing::blank(80, 60, Colour{60, 60, 60});
    for (int y = 0; y < im.height; ++y) {
      for (int x = 0; x < im.width; ++x) {
        testing::blend(im, x, y, Colour{190, 190, 190},
                       testing::coverage(x, y, [&](double u, double v) { return (u - x0) * nx + (v - y0) * ny > 0; }));
      }
    }
    const std::vector<LineSegment> lines = hough_line_segments(grey_of(im), im.width, im.height, CuttingPointParams{});
    ASSERT_FALSE(lines.empty()) << deg << " deg";
    const LineSegment truth{x0, y0, x0 + std::cos(a), y0 + std::sin(a)};
    bool on_edge = false;
    for (const LineSegment& s : lines) {
      on_edge |= line_distance(truth, s.x1, s.y1) <= 1.0 && line_distance(truth, s.x2, s.y2) <= 1.0 &&
                 std::hypot(s.x2 - s.x1, s.y2 - s.y1) >= 20;
    }
    EXPECT_TRUE(on_edge) << deg << " deg: no segment of 20 px within 1 px of the edge";
  }
}

// A rectangular "cluster" under a stalk: the ROI of Eq. 2 sits on the region's top,
// the line nearest the barycentre is a stalk edge, the cutting point its midpoint.
// (The ROI is half the barycentre's depth below the top: 30 px here, room for the
// paper's 20 px lines.)
TEST(CuttingPointDetection, TheMidpointOfTheStalkEdgeNearestTheBarycentre) {
  RgbImage im = testing::blank(200, 200, Colour{40, 110, 30});
  testing::draw_bar(im, 96.5, 103.5, 20, 100, Colour{150, 120, 60});  // the stalk, 7 px wide
  ClusterRegion region;
  region.width = region.height = 200;
  region.mask.assign(200 * 200, 0);
  for (int y = 100; y < 200; ++y) {
    for (int x = 60; x < 140; ++x) region.mask[static_cast<std::size_t>(y) * 200 + x] = 255;
  }
  region.area = 80 * 100;
  region.xc = 99.5, region.yc = 160, region.xt = 99.5, region.yt = 100, region.l_max = 79;
  region.x0 = 60, region.y0 = 100, region.x1 = 139, region.y1 = 199;
  const CuttingPointDetection d = detect_cutting_point(im, region, CuttingPointParams{});
  ASSERT_TRUE(d.found()) << d.failure;
  // ROI: 0.8 x 79 wide about x_c, 0.5 x 60 high above y_t.
  EXPECT_NEAR(d.roi_width, 0.8 * 79, 2);
  EXPECT_NEAR(d.roi_y, 100 - 0.5 * 60, 1);
  EXPECT_NEAR(std::abs(d.x - 100), 3.5, 1.0);  // on one of the two edges
  EXPECT_GT(d.y, d.roi_y);
  EXPECT_LT(d.y, 100);
  EXPECT_LT(d.distance, 5);
}

TEST(CuttingPointDetection, NoStalkNoLine) {
  RgbImage im = testing::blank(200, 200, Colour{40, 110, 30});
  ClusterRegion region;
  region.width = region.height = 200;
  region.area = 100, region.xc = 100, region.yc = 140, region.xt = 100, region.yt = 100, region.l_max = 80;
  const CuttingPointDetection d = detect_cutting_point(im, region, CuttingPointParams{});
  EXPECT_EQ(d.failure, "no line in the peduncle ROI");
  region.yt = 1;  // the cluster touches the top: nothing above it
  region.yc = 2;
  EXPECT_NE(detect_cutting_point(im, region, CuttingPointParams{}).failure.find("ROI is empty"), std::string::npos);
}

}  // namespace
}  // namespace grapebench
