// Analytic stereo pairs for seed 001's steps: discs, bars and textured backgrounds
// drawn with exact coverage (16 x 16 supersampling), each object shifted by its own
// disparity in the right image, so every answer is known.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

#include "algorithms/estimate.h"
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

// Seed 001's scene as an analytic pair: foliage far behind, a stalk and a cluster of 25
// shaded berries (16 px) each at its own disparity; f 1000 px, baseline 5 cm.
struct AnalyticPair {
  StereoPair pair;
  double stalk_x0 = 0, stalk_x1 = 0, stalk_y0 = 0, stalk_y1 = 0;  // left image, px
  double stalk_depth = 0;                                         // m
  std::vector<Vec3> berries;                                      // true front-surface centres, left camera, m
  std::vector<Circle> circles;                                    // left image, px
};

inline AnalyticPair analytic_pair() {
  AnalyticPair a;
  StereoPair& p = a.pair;
  p.fx = p.fy = 1000, p.cx = 399.5, p.cy = 299.5, p.baseline = 0.05;
  const auto depth_of = [&](double d) { return p.fx * p.baseline / d; };
  const double d_background = 40, d_stalk = 80;
  a.stalk_depth = depth_of(d_stalk);
  a.stalk_x0 = 396, a.stalk_x1 = 404, a.stalk_y0 = 120, a.stalk_y1 = 230;
  // Berries of 16 px (10 mm at 0.625 m) in rows, apart, disparities 78-82 px.
  struct B {
    double x, y, d, highlight;  // highlight: each berry its own, so NCC tells them apart
  };
  std::vector<B> berries;
  const int per_row[] = {5, 6, 5, 4, 3, 2};
  for (int row = 0; row < 6; ++row) {
    for (int k = 0; k < per_row[row]; ++k) {
      const double x = 400 + (k - 0.5 * (per_row[row] - 1)) * 33, y = 250 + row * 29;  // 1-1.4 px apart
      berries.push_back({x, y, 78.0 + ((row + k) % 3) * 2, 2.39996 * static_cast<double>(berries.size())});
    }
  }
  for (RgbImage* im : {&p.left, &p.right}) {
    const double side = im == &p.left ? 0 : 1;  // right image: everything moves left by its disparity
    *im = testing::blank(800, 600, Colour{40, 100, 28});
    testing::draw_foliage(*im, 21, side * d_background);
    testing::draw_bar(*im, a.stalk_x0 - side * d_stalk, a.stalk_x1 - side * d_stalk, a.stalk_y0, a.stalk_y1,
                      Colour{150, 125, 60});
    // Nearest last: higher disparity is nearer.
    std::vector<B> order = berries;
    std::stable_sort(order.begin(), order.end(), [](const B& l, const B& r) { return l.d < r.d; });
    for (const B& b : order) testing::draw_berry(*im, b.x - side * b.d, b.y, 16, b.highlight);
  }
  for (const B& b : berries) {
    const double z = depth_of(b.d);
    a.berries.push_back({(b.x - p.cx) * z / p.fx, (b.y - p.cy) * z / p.fy, z});
    a.circles.push_back({b.x, b.y, 16});
  }
  return a;
}

}  // namespace grapebench::testing
