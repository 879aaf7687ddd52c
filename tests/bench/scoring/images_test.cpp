// CIEDE2000 against Sharma, Wu and Dalal's (2005) test pairs; SSIM's fixed points.
#include "bench/scoring/images.h"

#include <gtest/gtest.h>

#include <cmath>

namespace grapebench {
namespace {

TEST(ImageScores, Ciede2000MatchesSharmasTestData) {
  struct Pair {
    double l1, a1, b1, l2, a2, b2, de;
  };
  // Rows 1, 7, 17, 25 and 34 of Sharma et al.'s Table 1.
  const Pair pairs[] = {{50, 2.6772, -79.7751, 50, 0, -82.7485, 2.0425},
                        {50, 0, 0, 50, -1, 2, 2.3669},
                        {50, 2.5, 0, 73, 25, -18, 27.1492},
                        {60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644},
                        {22.7233, 20.0904, -46.6940, 23.0331, 14.9730, -42.5619, 2.0373}};
  for (const Pair& p : pairs) {
    EXPECT_NEAR(ciede2000({p.l1, p.a1, p.b1}, {p.l2, p.a2, p.b2}), p.de, 1e-4);
    EXPECT_NEAR(ciede2000({p.l2, p.a2, p.b2}, {p.l1, p.a1, p.b1}), p.de, 1e-4);  // symmetric
  }
  EXPECT_EQ(ciede2000({40, 10, -5}, {40, 10, -5}), 0.0);
}

TEST(ImageScores, LabOfWhiteGreyAndBlack) {
  const Eigen::Vector3d white = srgb8_to_lab(255, 255, 255), black = srgb8_to_lab(0, 0, 0);
  EXPECT_NEAR(white[0], 100, 1e-3);
  EXPECT_NEAR(white[1], 0, 1e-2);
  EXPECT_NEAR(white[2], 0, 1e-2);
  EXPECT_NEAR(black[0], 0, 1e-9);
  EXPECT_NEAR(srgb8_to_lab(119, 119, 119)[0], 50, 0.3);  // sRGB 119 is L* 50
}

TEST(ImageScores, SsimIsOneForTheSameImageAndFallsWithNoise) {
  const int W = 48, H = 32;
  std::vector<std::uint8_t> a(3 * W * H), b;
  for (std::size_t i = 0; i < a.size(); ++i) a[i] = static_cast<std::uint8_t>((i * 37) % 251);
  EXPECT_NEAR(luminance_ssim(a, a, W, H), 1.0, 1e-12);
  b = a;
  for (std::size_t i = 0; i < b.size(); i += 7) b[i] = static_cast<std::uint8_t>(255 - b[i]);
  const double s = luminance_ssim(a, b, W, H);
  EXPECT_LT(s, 0.95);
  EXPECT_GT(s, -1.0);
  EXPECT_THROW(luminance_ssim(a, std::vector<std::uint8_t>(3), W, H), std::invalid_argument);
}

// Green spikes of +10 DN on every fifth pixel of a diagonal pattern: at most 3 in any
// 3 x 3 window, so the median stays flat and the residual is 10 on exactly a fifth of
// the 40 x 30 inner pixels: sd 10 sqrt(0.2 - 0.04) = 4 DN in green, 0 in red and blue.
TEST(ImageScores, PixelNoiseIsTheSpreadAboutTheThreeByThreeMedian) {
  const int W = 42, H = 32;
  std::vector<std::uint8_t> rgb(3 * W * H, 100);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if ((x + y) % 5 == 0) rgb[3 * (static_cast<std::size_t>(y) * W + x) + 1] = 110;
  const std::vector<int> cls(static_cast<std::size_t>(W) * H, 0);
  PixelNoise noise = pixel_noise(rgb, cls, W, H, 2);
  ASSERT_EQ(noise.pixels.size(), 2u);
  EXPECT_EQ(noise.pixels[0], 40 * 30);  // the border rows and columns left out
  EXPECT_EQ(noise.pixels[1], 0);
  const auto sd = noise.sd(0);
  EXPECT_NEAR(sd[0], 0.0, 1e-12);
  EXPECT_NEAR(sd[1], 4.0, 1e-12);
  EXPECT_NEAR(sd[2], 0.0, 1e-12);
  EXPECT_TRUE(std::isnan(noise.sd(1)[1]));
  // Views pool by their sums: the same view twice, twice the pixels, the same sd.
  noise.add(pixel_noise(rgb, cls, W, H, 2));
  EXPECT_EQ(noise.pixels[0], 2 * 40 * 30);
  EXPECT_NEAR(noise.sd(0)[1], 4.0, 1e-12);
}

// Pixels at a class's edge do not count: bright one-pixel dots of class 1 on a flat
// class 0 give no class-1 pixel and no spread in class 0 (counted, the dots would read
// as 150 DN of noise).
TEST(ImageScores, PixelNoiseLeavesOutEdgesAndRefusesBadSizes) {
  const int W = 24, H = 20;
  std::vector<std::uint8_t> rgb(3 * W * H, 50);
  std::vector<int> cls(static_cast<std::size_t>(W) * H, 0);
  for (int y = 2; y < H; y += 4)
    for (int x = 2; x < W; x += 4) {
      const std::size_t i = static_cast<std::size_t>(y) * W + x;
      cls[i] = 1;
      for (int ch = 0; ch < 3; ++ch) rgb[3 * i + ch] = 200;
    }
  const PixelNoise noise = pixel_noise(rgb, cls, W, H, 2);
  EXPECT_EQ(noise.pixels[1], 0);
  EXPECT_GT(noise.pixels[0], 0);
  for (const double v : noise.sd(0)) EXPECT_EQ(v, 0.0);
  EXPECT_THROW(pixel_noise(rgb, std::vector<int>(3, 0), W, H, 2), std::invalid_argument);
  cls[5] = 2;  // outside [-1, 2)
  EXPECT_THROW(pixel_noise(rgb, cls, W, H, 2), std::invalid_argument);
}

}  // namespace
}  // namespace grapebench
