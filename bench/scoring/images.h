// Scores of one colour image against a reference image of the same view (a renderer
// against the physically based reference; later, a camera model against a photo):
// CIE L*a*b* colours, the CIEDE2000 colour difference and luminance SSIM.
#pragma once

#include <Eigen/Core>

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

}  // namespace grapebench
