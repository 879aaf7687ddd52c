#include "algorithms/stereo/berry_circles.h"

#include <gtest/gtest.h>

#include "algorithms/stereo/stereo_drawing.h"

namespace grapebench {
namespace {

using testing::Colour;

ClusterRegion box_region(int w, int h, int x0, int y0, int x1, int y1) {
  ClusterRegion r;
  r.width = w, r.height = h;
  r.mask.assign(static_cast<std::size_t>(w) * h, 0);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) r.mask[static_cast<std::size_t>(y) * w + x] = 255;
  }
  r.area = (x1 - x0 + 1) * (y1 - y0 + 1);
  r.x0 = x0, r.y0 = y0, r.x1 = x1, r.y1 = y1;
  return r;
}

TEST(BerryCircles, KasaFitIsExactOnACircle) {
  std::vector<double> x, y;
  for (int k = 0; k < 9; ++k) x.push_back(3.25 + 17.5 * std::cos(0.4 * k)), y.push_back(-8 + 17.5 * std::sin(0.4 * k));
  const auto c = fit_circle(x, y);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->x, 3.25, 1e-9);
  EXPECT_NEAR(c->y, -8, 1e-9);
  EXPECT_NEAR(c->r, 17.5, 1e-9);
  EXPECT_FALSE(fit_circle({0, 1, 2}, {0, 1, 2}));  // collinear
  EXPECT_FALSE(fit_circle({0, 1}, {0, 1}));
}

// One shaded disc at a sub-pixel centre: found within 0.5 px in centre and radius.
TEST(BerryCircles, ADiscIsFoundWithinHalfAPixel) {
  for (const auto& [cx, cy, r] : {std::array{200.3, 150.7, 18.4}, std::array{190.0, 160.25, 24.6}}) {
    RgbImage im = testing::blank(400, 300, Colour{40, 110, 30});
    testing::draw_berry(im, cx, cy, r);
    const ClusterRegion region = box_region(400, 300, int(cx - r), int(cy - r), int(cx + r), int(cy + r));
    BerryCircleParams p;
    p.radius_model = BerryCircleParams::RadiusModel::Pinhole;  // 8-20 mm at 0.6 m: 13.3-33.3 px
    const BerryCircles b = detect_berries(im, region, 0.6, 1000, p);
    ASSERT_EQ(b.berries.size(), 1u) << "candidates " << b.candidates;
    EXPECT_NEAR(b.berries[0].circle.x, cx, 0.5);
    EXPECT_NEAR(b.berries[0].circle.y, cy, 0.5);
    EXPECT_NEAR(b.berries[0].circle.r, r, 0.5);
  }
}

// Eq. 6 against the pinhole model: the fitted law implies f of about 1250 px at
// 350 mm and about 1040 px at 1100 mm (shared/notes/seeds-001-004.md).
TEST(BerryCircles, RadiusWindowOfEq6AndOfThePinhole) {
  BerryCircleParams p;
  const RadiusWindow near = berry_radius_window(p, 0.35, 1000), far = berry_radius_window(p, 1.1, 1000);
  EXPECT_NEAR(near.r_min, 3185 * 8 * std::pow(350.0, -1.16), 1e-9);
  EXPECT_NEAR(far.r_max, 3185 * 20 * std::pow(1100.0, -1.16), 1e-9);
  EXPECT_NEAR(near.r_min / (0.008 / 0.35), 1250, 15);
  EXPECT_NEAR(far.r_min / (0.008 / 1.1), 1040, 15);
  p.radius_model = BerryCircleParams::RadiusModel::Pinhole;
  const RadiusWindow pin = berry_radius_window(p, 0.8, 1000);
  EXPECT_NEAR(pin.r_min, 10, 1e-12);
  EXPECT_NEAR(pin.r_max, 25, 1e-12);
}

// Eq. 7: a circle centred off the cluster region is dropped.
TEST(BerryCircles, CentresOffTheRegionAreDropped) {
  RgbImage im = testing::blank(400, 300, Colour{40, 110, 30});
  testing::draw_berry(im, 100, 150, 20);
  testing::draw_berry(im, 180, 150, 20);
  BerryCircleParams p;
  p.radius_model = BerryCircleParams::RadiusModel::Pinhole;
  ClusterRegion region = box_region(400, 300, 70, 120, 210, 180);  // searched: both discs
  for (int y = 0; y < 300; ++y) {
    for (int x = 131; x < 400; ++x) region.mask[static_cast<std::size_t>(y) * 400 + x] = 0;  // S_GC: the first only
  }
  const BerryCircles b = detect_berries(im, region, 0.6, 1000, p);
  EXPECT_GE(b.candidates, 2);
  ASSERT_EQ(b.berries.size(), 1u);
  EXPECT_NEAR(b.berries[0].circle.x, 100, 0.5);
}

}  // namespace
}  // namespace grapebench
