// Analytic stereo pairs for seed 001's steps: discs, bars and textured backgrounds
// drawn with exact coverage (16 x 16 supersampling), each object shifted by its own
// disparity in the right image, so every answer is known.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

#include "algorithms/stereo_pair.h"
#include "synth/rng.h"

namespace grapebench::testing {

using Colour = std::array<double, 3>;  // 0-255

// Fraction of pixel (x, y) (centre at integer coordinates) inside a shape.
inline double coverage(int x, int y, const std::function<bool(double, double)>& inside) {
  int n = 0;
  for (int i = 0; i < 16; ++i) {
    for (int j = 0; j < 16; ++j) n += inside(x - 0.5 + (i + 0.5) / 16, y - 0.5 + (j + 0.5) / 16);
  }
  return n / 256.0;
}

inline void blend(RgbImage& im, int x, int y, const Colour& c, double a) {
  if (a <= 0 || x < 0 || y < 0 || x >= im.width || y >= im.height) return;
  std::uint8_t* p = im.data.data() + (static_cast<std::size_t>(y) * im.width + x) * 3;
  for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>(std::lround((1 - a) * p[k] + a * c[k]));
}

inline RgbImage blank(int w, int h, const Colour& c) {
  RgbImage im{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h * 3)};
  for (std::size_t i = 0; i < im.data.size(); ++i) im.data[i] = static_cast<std::uint8_t>(c[i % 3]);
  return im;
}

// Leaf-green blobs, deterministic in `seed`, shifted left by `shift` px (the right image).
inline void draw_foliage(RgbImage& im, std::uint64_t seed, double shift) {
  Rng rng(seed);
  for (int b = 0; b < 400; ++b) {
    const double cx = rng.uniform(-200, im.width + 200) - shift, cy = rng.uniform(0, im.height), r = rng.uniform(6, 30);
    const double shade = rng.uniform(0.6, 1.3);
    const Colour c{40 * shade, 100 * shade, 25 * shade};
    for (int y = static_cast<int>(cy - r) - 1; y <= cy + r + 1; ++y) {
      for (int x = static_cast<int>(cx - r) - 1; x <= cx + r + 1; ++x) {
        blend(im, x, y, c,
              coverage(x, y, [&](double u, double v) { return (u - cx) * (u - cx) + (v - cy) * (v - cy) < r * r; }));
      }
    }
  }
}

// A shaded berry: dark purple, lighter towards an off-centre highlight (at angle
// `highlight` rad about the centre), so its edge and its inside have texture.
inline void draw_berry(RgbImage& im, double cx, double cy, double r, double highlight = -2.356) {
  const double hx = cx + 0.42 * r * std::cos(highlight), hy = cy + 0.42 * r * std::sin(highlight);
  for (int y = static_cast<int>(cy - r) - 1; y <= cy + r + 1; ++y) {
    for (int x = static_cast<int>(cx - r) - 1; x <= cx + r + 1; ++x) {
      const double a =
          coverage(x, y, [&](double u, double v) { return (u - cx) * (u - cx) + (v - cy) * (v - cy) < r * r; });
      const double d = std::hypot(x - hx, y - hy) / r;
      const double k = std::clamp(1.0 - 0.8 * d, 0.0, 1.0);
      blend(im, x, y, {50 + 150 * k * k, 25 + 120 * k * k, 60 + 150 * k * k}, a);
    }
  }
}

// A vertical stalk [x0, x1] x [y0, y1], brown-green.
inline void draw_bar(RgbImage& im, double x0, double x1, double y0, double y1, const Colour& c) {
  for (int y = static_cast<int>(y0) - 1; y <= y1 + 1; ++y) {
    for (int x = static_cast<int>(x0) - 1; x <= x1 + 1; ++x) {
      blend(im, x, y, c, coverage(x, y, [&](double u, double v) { return u >= x0 && u <= x1 && v >= y0 && v <= y1; }));
    }
  }
}

}  // namespace grapebench::testing
