#include "algorithms/stereo/ncc_disparity.h"

#include <gtest/gtest.h>

#include <cmath>

namespace grapebench {
namespace {

// A band-limited texture (a sum of plane waves) and its exact shift by `d` px:
// right(x) = left(x + d), no interpolation.
struct ShiftedPair {
  GreyImage left, right;
};
double texture(double x, double y) {
  return 128 + 40 * std::sin(0.31 * x + 0.17 * y) + 30 * std::sin(0.13 * x - 0.41 * y + 1) +
         25 * std::sin(0.53 * x + 0.07 * y + 2) + 15 * std::sin(0.023 * x * x / 40 + 0.2 * y);
}
ShiftedPair shifted_texture(double d) {
  ShiftedPair p;
  for (GreyImage* g : {&p.left, &p.right}) *g = GreyImage{400, 120, std::vector<std::uint8_t>(400 * 120)};
  for (int y = 0; y < 120; ++y) {
    for (int x = 0; x < 400; ++x) {
      p.left.data[static_cast<std::size_t>(y) * 400 + x] = static_cast<std::uint8_t>(std::lround(texture(x, y)));
      p.right.data[static_cast<std::size_t>(y) * 400 + x] = static_cast<std::uint8_t>(std::lround(texture(x + d, y)));
    }
  }
  return p;
}

TEST(NccDisparity, RecoversTheShiftOfATexture) {
  NccParams p;  // 9 x 9, 0.92, 350-1100 mm: 45-143 px at f = 1000 px, B = 5 cm
  for (double d : {60.0, 83.0, 100.4, 121.7}) {
    const ShiftedPair pair = shifted_texture(d);
    for (const double x : {250.0, 300.0, 330.0}) {
      const NccMatch m = ncc_disparity(pair.left, pair.right, x, 60, 1000, 0.05, p);
      ASSERT_TRUE(m.ok()) << m.failure;
      EXPECT_NEAR(m.disparity, d, 0.5) << "x " << x;
      EXPECT_GT(m.score, 0.92);
    }
  }
}

TEST(NccDisparity, RejectsFlatWindowsLowScoresAndTheBorder) {
  const ShiftedPair pair = shifted_texture(80);
  GreyImage flat = pair.left;
  std::fill(flat.data.begin(), flat.data.end(), 100);
  NccParams p;
  EXPECT_NE(ncc_disparity(flat, pair.right, 300, 60, 1000, 0.05, p).failure.find("flat"), std::string::npos);
  EXPECT_NE(ncc_disparity(pair.left, pair.right, 2, 60, 1000, 0.05, p).failure.find("leaves the image"),
            std::string::npos);
  // The true disparity (80 px) lies outside a search for 1.0-1.1 m (45-50 px).
  p.depth_min = 1.0;
  const NccMatch far = ncc_disparity(pair.left, pair.right, 300, 60, 1000, 0.05, p);
  EXPECT_FALSE(far.ok());
  EXPECT_NE(far.failure.find("below the accepted"), std::string::npos);
}

}  // namespace
}  // namespace grapebench
