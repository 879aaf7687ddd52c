// Deterministic random numbers: xoshiro256** seeded through splitmix64, with our own
// uniform and normal transforms, so a seed gives the same bunch on every compiler and
// standard library (std::normal_distribution is implementation-defined).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace grapebench {

inline std::uint64_t splitmix64(std::uint64_t& x) {
  std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Derives an independent stream seed from a parent seed and an index (a bunch, a
// view), so work items can run in any order or thread and still draw the same numbers.
inline std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t index) {
  std::uint64_t x = seed ^ (0x632be59bd9b4e019ULL * (index + 1));
  splitmix64(x);
  return splitmix64(x);
}

// Stateless draws for per-pixel noise: uniform in (0, 1) from a hash of (seed,
// counter), and a standard normal by inverse CDF (Acklam's rational approximation,
// relative error below 1.2e-9; no transcendental function in the central 95 %).
inline double hashed_uniform(std::uint64_t seed, std::uint64_t counter) {
  std::uint64_t x = seed ^ (counter * 0xd1342543de82ef95ULL);
  const std::uint64_t h = splitmix64(x);
  return (static_cast<double>(h >> 11) + 0.5) * 0x1.0p-53;
}
inline double inverse_normal_cdf(double p) {
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                                 1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                 6.680131188771972e+01, -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                 -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                                 3.754408661907416e+00};
  if (p < 0.02425) {
    const double q = std::sqrt(-2 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  if (p > 1 - 0.02425) return -inverse_normal_cdf(1 - p);
  const double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
}
inline double hashed_normal(std::uint64_t seed, std::uint64_t counter) {
  return inverse_normal_cdf(hashed_uniform(seed, counter));
}

// The same draw through a table of the inverse CDF (8192 cells, linear interpolation)
// in the central 95 %, the formula in the tails: cheaper, for per-pixel noise
// drawn for every pixel of a frame. The interpolation error is below 2e-6 standard
// deviations (tests/synth/rng_test.cpp).
struct NormalTable {
  static constexpr int kCells = 8192;
  static constexpr double kLo = 0.02425, kHi = 1 - 0.02425;
  float value[kCells + 1];  // float: 32 KiB, the table stays in L1
  NormalTable() {
    for (int i = 0; i <= kCells; ++i) value[i] = static_cast<float>(inverse_normal_cdf(kLo + (kHi - kLo) * i / kCells));
  }
  // The tails out of line, so the central path inlines into per-pixel loops.
  [[gnu::noinline]] static double tail(double p) { return inverse_normal_cdf(p); }
  double operator()(double p) const {
    if (p < kLo || p > kHi) [[unlikely]] return tail(p);
    const double x = (p - kLo) * (kCells / (kHi - kLo));
    const int i = std::min(static_cast<int>(x), kCells - 1);
    const double f = x - i;
    return value[i] + f * (static_cast<double>(value[i + 1]) - value[i]);
  }
};
// Namespace scope rather than a function's static: no guard on every draw. Safe for
// any global defined after this header's inclusion (inline variables initialise in
// definition order within a translation unit); no static initialiser draws noise.
inline const NormalTable kNormalTable;
inline double hashed_normal_tabulated(std::uint64_t seed, std::uint64_t counter) {
  return kNormalTable(hashed_uniform(seed, counter));
}

class Rng {
 public:
  explicit Rng(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (auto& w : s_) w = splitmix64(x);
  }
  std::uint64_t next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  // Uniform in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [lo, hi].
  int uniform_int(int lo, int hi) {
    const auto span = static_cast<std::uint64_t>(hi - lo) + 1;
    return lo + static_cast<int>(next() % span);
  }
  // Standard normal by Box-Muller (one value per call; the pair's second is dropped
  // so the stream position never depends on call history).
  double normal() {
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
  double normal(double mean, double sd) { return mean + sd * normal(); }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
};

}  // namespace grapebench
