// Scores of one colour image against a reference image of the same view (a renderer
// against the physically based reference; later, a camera model against a photo):
// CIE L*a*b* colours, the CIEDE2000 colour difference and luminance SSIM.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace grapebench {

// CIE L*a*b* (D65 white) of linear sRGB primaries (IEC 61966-2-1's matrix), and of
// 8-bit sRGB values (decoded first).
Eigen::Vector3d linear_rgb_to_lab(const Eigen::Vector3d& rgb);
Eigen::Vector3d srgb8_to_lab(std::uint8_t r, std::uint8_t g, std::uint8_t b);
// An 8-bit sRGB value decoded to linear [0, 1] (IEC 61966-2-1).
double srgb8_to_linear(std::uint8_t v);

// CIEDE2000 (kL = kC = kH = 1), as Sharma, Wu and Dalal (2005) give it with their
// test data (tests/bench/scoring/images_test.cpp checks it against that table).
double ciede2000(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2);

// Mean SSIM (Wang, Bovik, Sheikh and Simoncelli 2004: Gaussian window of 11 px,
// sigma 1.5, K1 0.01, K2 0.03, L 255) of the Rec. 709 luma of two 8-bit sRGB images
// (H x W x 3, top row first). Throws std::invalid_argument on a size mismatch.
double luminance_ssim(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, int width, int height);

// An 8-bit RGB image's pixel noise per class: each channel's residual about its 3 x 3
// median (DN), over the pixels whose whole 3 x 3 neighbourhood is of that class (so
// edges and other classes do not count; the image's border rows and columns neither).
// Sums, so that views pool by add(); sd() is the population standard deviation (the
// measure of scripts/pixel_noise.py, docs/seed004.md "Against Cycles").
struct PixelNoise {
  std::vector<long long> pixels;                  // per class
  std::vector<std::array<long long, 3>> sum, sum_sq;  // per class, R, G, B residuals (DN, DN^2)

  void add(const PixelNoise& other);
  std::array<double, 3> sd(std::size_t cls) const;  // DN, R G B; NaN without pixels
};
// rgb: H x W x 3, top row first; cls: H x W, the class of each pixel in [0, classes)
// or -1 for none. Throws std::invalid_argument on a size mismatch or a class outside.
PixelNoise pixel_noise(const std::vector<std::uint8_t>& rgb, const std::vector<int>& cls, int width, int height,
                       int classes);

}  // namespace grapebench
