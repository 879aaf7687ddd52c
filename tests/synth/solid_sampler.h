// Test helper: an independent inside test for a bunch's solid (balls and stem
// cylinders straight from their definitions, no volume decomposition) and a seeded
// Monte Carlo volume estimate with its standard error.
#pragma once

#include "synth/rng.h"
#include "synth/stem_geometry.h"
#include "synth/types.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace grapebench::testing {

struct MonteCarloVolume {
  double volume = 0;
  double standard_error = 0;
};

class SolidSampler {
 public:
  explicit SolidSampler(const Bunch& b) : bunch_(b) {
    lo_ = Vec3::Constant(1e30);
    hi_ = Vec3::Constant(-1e30);
    for (const auto& x : b.berries) grow(x.centre, x.radius);
    for (const auto& s : b.stems) {
      grow(s.start, s.radius);
      grow(s.end, s.radius);
    }
    cell_ = 0.01;
    for (int k = 0; k < 3; ++k) n_[k] = std::max(1, static_cast<int>(std::ceil((hi_[k] - lo_[k]) / cell_)));
    cells_.resize(static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]);
    for (int i = 0; i < static_cast<int>(b.berries.size()); ++i) {
      const auto& x = b.berries[i];
      insert(x.centre - Vec3::Constant(x.radius), x.centre + Vec3::Constant(x.radius), i);
    }
    for (int i = 0; i < static_cast<int>(b.stems.size()); ++i) {
      const auto& s = b.stems[i];
      insert(s.start.cwiseMin(s.end) - Vec3::Constant(s.radius), s.start.cwiseMax(s.end) + Vec3::Constant(s.radius),
             -1 - i);
    }
  }
  bool inside(const Vec3& x) const {
    for (int id : cells_[index(x)]) {
      if (id >= 0) {
        const auto& b = bunch_.berries[id];
        if ((x - b.centre).squaredNorm() <= b.radius * b.radius) return true;
      } else if (inside_stem(bunch_.stems[-1 - id], x)) {
        return true;
      }
    }
    return false;
  }
  MonteCarloVolume estimate(long samples, std::uint64_t seed) const {
    Rng rng(seed);
    long hits = 0;
    for (long i = 0; i < samples; ++i) {
      const Vec3 x(rng.uniform(lo_.x(), hi_.x()), rng.uniform(lo_.y(), hi_.y()), rng.uniform(lo_.z(), hi_.z()));
      hits += inside(x);
    }
    const double box = (hi_ - lo_).prod(), p = static_cast<double>(hits) / samples;
    return {box * p, box * std::sqrt(p * (1 - p) / samples)};
  }

 private:
  void grow(const Vec3& c, double r) {
    lo_ = lo_.cwiseMin(c - Vec3::Constant(r));
    hi_ = hi_.cwiseMax(c + Vec3::Constant(r));
  }
  int clampi(double v, int k) const { return std::clamp(static_cast<int>((v - lo_[k]) / cell_), 0, n_[k] - 1); }
  std::size_t index(const Vec3& x) const {
    return (static_cast<std::size_t>(clampi(x.z(), 2)) * n_[1] + clampi(x.y(), 1)) * n_[0] + clampi(x.x(), 0);
  }
  void insert(const Vec3& a, const Vec3& b, int id) {
    for (int z = clampi(a.z(), 2); z <= clampi(b.z(), 2); ++z)
      for (int y = clampi(a.y(), 1); y <= clampi(b.y(), 1); ++y)
        for (int x = clampi(a.x(), 0); x <= clampi(b.x(), 0); ++x)
          cells_[(static_cast<std::size_t>(z) * n_[1] + y) * n_[0] + x].push_back(id);
  }
  const Bunch& bunch_;
  Vec3 lo_, hi_;
  double cell_;
  int n_[3];
  std::vector<std::vector<int>> cells_;
};

}  // namespace grapebench::testing
