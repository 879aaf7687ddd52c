// The camera chain of sensors/render/develop_image.h against what each stage must do:
// the Bayer pattern's naming in OpenCV, shot noise of sqrt(electrons), the metering
// rule, the cos^4 law, JPEG, determinism.
#include "sensors/render/develop_image.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace grapebench {
namespace {

Intrinsics small(int w = 64, int h = 48) {
  Intrinsics k;
  k.width = w;
  k.height = h;
  k.fx = k.fy = 60;
  k.cx = 0.5 * w;
  k.cy = 0.5 * h;
  return k;
}
std::vector<float> flat(const Intrinsics& k, float r, float g, float b) {
  std::vector<float> v;
  for (int i = 0; i < k.width * k.height; ++i) v.insert(v.end(), {r, g, b});
  return v;
}
PhotoCameraParams noiseless() {
  PhotoCameraParams p;
  p.full_well = 1e6;
  p.read_noise = 0;
  p.vignetting = 0;
  p.exposure = PhotoCameraParams::Exposure::Fixed;
  p.exposure_gain = 1;
  p.adc_bits = 16;
  return p;
}

// An RGGB mosaic demosaiced as OpenCV's BayerBG: a pure primary stays that primary
// (a wrong pattern name swaps red and blue).
TEST(DevelopImage, TheBayerMosaicKeepsEachPrimaryInItsChannel) {
  const Intrinsics k = small();
  for (auto mode : {PhotoCameraParams::Demosaic::Bilinear, PhotoCameraParams::Demosaic::EdgeAware}) {
    PhotoCameraParams p = noiseless();
    p.demosaic = mode;
    for (int c = 0; c < 3; ++c) {
      const DevelopResult d = develop_image(flat(k, c == 0 ? 0.5f : 0, c == 1 ? 0.5f : 0, c == 2 ? 0.5f : 0), k, p, 1);
      // An inner pixel (the border is interpolated from fewer neighbours).
      const std::size_t i = 3 * (static_cast<std::size_t>(20) * k.width + 30);
      const int want = static_cast<int>(std::lround(255 * srgb_encode(0.5)));
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(d.rgb[i + ch], ch == c ? want : 0, 2) << "primary " << c << " channel " << ch;
    }
  }
}

// Photon shot noise: a flat field of e electrons has sd sqrt(e); at 18 % of a 10 ke-
// well that is 0.42 % of full scale, 1.29 of 255 after the sRGB slope at 0.18.
TEST(DevelopImage, ShotNoiseIsTheSquareRootOfTheElectrons) {
  const Intrinsics k = small(200, 150);
  PhotoCameraParams p = noiseless();
  p.full_well = 10000;
  p.bayer = PhotoCameraParams::Bayer::None;
  const DevelopResult d = develop_image(flat(k, 0.18f, 0.18f, 0.18f), k, p, 3);
  double sum = 0, sq = 0;
  const std::size_t n = d.rgb.size();
  for (std::uint8_t v : d.rgb) sum += v, sq += static_cast<double>(v) * v;
  const double mean = sum / n, sd = std::sqrt(sq / n - mean * mean);
  const double slope = 1.055 / 2.4 * std::pow(0.18, 1 / 2.4 - 1) * 255;
  const double want = std::sqrt(std::pow(std::sqrt(1800.0) / 10000 * slope, 2) + 1.0 / 12);  // and 8-bit rounding
  std::printf("[develop] flat 0.18 at 10 ke-: mean %.2f, sd %.3f (expected %.3f)\n", mean, sd, want);
  EXPECT_NEAR(mean, 255 * srgb_encode(0.18), 0.3);
  EXPECT_NEAR(sd, want, 0.08 * want);
}

// Average metering puts any flat scene's mean at the target (118 of 255 for 18 %),
// and a synchronised right camera reuses the left's gain.
TEST(DevelopImage, AutoExposureMetersTheMeanToTheTarget) {
  const Intrinsics k = small();
  PhotoCameraParams p = noiseless();
  p.exposure = PhotoCameraParams::Exposure::Auto;
  for (float level : {0.01f, 0.3f, 4.0f}) {
    const DevelopResult d = develop_image(flat(k, level, level, level), k, p, 1);
    EXPECT_NEAR(d.gain * level, 0.18, 1e-6);
    EXPECT_NEAR(d.rgb[3 * 500], 118, 1);
    const DevelopResult again = develop_image(flat(k, 2 * level, 2 * level, 2 * level), k, p, 1, d.gain);
    EXPECT_DOUBLE_EQ(again.gain, d.gain);
  }
}

// Natural vignetting: a corner over the centre is cos^4 of its field angle.
TEST(DevelopImage, VignettingFollowsTheCosFourthLaw) {
  const Intrinsics k = small();
  PhotoCameraParams p = noiseless();
  p.vignetting = 1;
  p.bayer = PhotoCameraParams::Bayer::None;
  const DevelopResult d = develop_image(flat(k, 0.5f, 0.5f, 0.5f), k, p, 1);
  const auto linear = [](std::uint8_t v) {
    const double s = v / 255.0;
    return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
  };
  const double dx = (0.5 - k.cx) / k.fx, dy = (0.5 - k.cy) / k.fy, c2 = 1 / (1 + dx * dx + dy * dy);
  const double ratio = linear(d.rgb[0]) / 0.5;
  EXPECT_NEAR(ratio, c2 * c2, 0.01);
}

TEST(DevelopImage, JpegIsLossyAndEverythingIsRepeatable) {
  const Intrinsics k = small();
  PhotoCameraParams p;
  std::vector<float> img;
  for (int i = 0; i < k.width * k.height; ++i) img.insert(img.end(), {0.1f * (i % 7), 0.05f * (i % 11), 0.02f * (i % 13)});
  const DevelopResult a = develop_image(img, k, p, 5), b = develop_image(img, k, p, 5), c = develop_image(img, k, p, 6);
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_NE(a.rgb, c.rgb);  // another seed, other noise
  p.jpeg_quality = 50;
  const DevelopResult j = develop_image(img, k, p, 5);
  EXPECT_EQ(j.rgb.size(), a.rgb.size());
  EXPECT_NE(j.rgb, a.rgb);
  EXPECT_EQ(j.rgb, develop_image(img, k, p, 5).rgb);
  EXPECT_THROW(develop_image(std::vector<float>(10), k, p, 1), InputError);
}

}  // namespace
}  // namespace grapebench
