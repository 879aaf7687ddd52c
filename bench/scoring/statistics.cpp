#include "bench/scoring/statistics.h"

#include "bench/scoring/rates.h"

#include "bench/scoring/scalars.h"
#include "synth/rng.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <utility>

namespace grapebench {

Interval percentile_interval(std::vector<double> v, double level) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return {kNaN, kNaN};
  const double tail = (1 - level) / 2;
  return {quantile(v, tail), quantile(v, 1 - tail)};
}

namespace {

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// Bias-corrected and accelerated bootstrap interval (Efron 1987; Efron and Tibshirani
// 1993, Eqs. 14.9-14.15): z0 from the share of resamples below the estimate, the
// acceleration from the jackknife's skewness; falls back to the percentile interval
// where those are undefined (a constant statistic).
Interval bca_interval(std::vector<double> boot, const std::vector<double>& jack, double estimate, double level) {
  boot.erase(std::remove_if(boot.begin(), boot.end(), [](double x) { return !std::isfinite(x); }), boot.end());
  if (boot.empty() || !std::isfinite(estimate)) return {kNaN, kNaN};
  double below = 0;
  for (double b : boot) below += b < estimate ? 1.0 : b == estimate ? 0.5 : 0.0;
  const double share = below / static_cast<double>(boot.size());
  double jm = 0, num = 0, den = 0;
  int jn = 0;
  for (double j : jack) {
    if (std::isfinite(j)) {
      jm += j;
      ++jn;
    }
  }
  if (jn < 2 || share <= 0 || share >= 1) return percentile_interval(boot, level);
  jm /= jn;
  for (double j : jack) {
    if (!std::isfinite(j)) continue;
    const double d = jm - j;
    num += d * d * d;
    den += d * d;
  }
  if (den <= 0) return percentile_interval(boot, level);
  const double a = num / (6 * std::pow(den, 1.5));
  const double z0 = inverse_normal_cdf(share);
  const double tail = (1 - level) / 2;
  const auto adjusted = [&](double q) {
    const double z = z0 + inverse_normal_cdf(q);
    return normal_cdf(z0 + z / (1 - a * z));
  };
  return {quantile(boot, adjusted(tail)), quantile(boot, adjusted(1 - tail))};
}

}  // namespace

ScoreIntervals bootstrap_score_intervals(const std::vector<double>& est, const std::vector<double>& truth,
                                         std::uint64_t seed, int resamples, double level) {
  ScoreIntervals out;
  const std::size_t n = est.size();
  if (n < 3) {
    out.rmse = out.bias = out.mape = out.r2 = {kNaN, kNaN};
    return out;
  }
  const std::vector<double> no_times;
  // The four statistics of one sample.
  const auto stats = [&](const std::vector<double>& e, const std::vector<double>& t) {
    const Score s = score(e, t, static_cast<int>(e.size()), no_times);
    return std::array<double, 4>{s.rmse, s.bias, s.mape, s.r2};
  };
  const std::array<double, 4> full = stats(est, truth);
  Rng rng(seed);
  std::array<std::vector<double>, 4> boot;
  std::vector<double> e(n), t(n);
  for (int b = 0; b < resamples; ++b) {
    for (std::size_t i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(rng.next() % n);
      e[i] = est[k];
      t[i] = truth[k];
    }
    const auto v = stats(e, t);
    for (int k = 0; k < 4; ++k) boot[static_cast<std::size_t>(k)].push_back(v[static_cast<std::size_t>(k)]);
  }
  // Jackknife (leave one case out) for the acceleration.
  std::array<std::vector<double>, 4> jack;
  for (std::size_t drop = 0; drop < n; ++drop) {
    std::vector<double> je, jt;
    for (std::size_t i = 0; i < n; ++i) {
      if (i == drop) continue;
      je.push_back(est[i]);
      jt.push_back(truth[i]);
    }
    const auto v = stats(je, jt);
    for (int k = 0; k < 4; ++k) jack[static_cast<std::size_t>(k)].push_back(v[static_cast<std::size_t>(k)]);
  }
  Interval* targets[4] = {&out.rmse, &out.bias, &out.mape, &out.r2};
  for (std::size_t k = 0; k < 4; ++k) *targets[k] = bca_interval(boot[k], jack[k], full[k], level);
  return out;
}

double concordance(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  if (n < 2) return kNaN;
  const double dn = static_cast<double>(n);
  const double mx = std::accumulate(x.begin(), x.end(), 0.0) / dn, my = std::accumulate(y.begin(), y.end(), 0.0) / dn;
  double sxx = 0, syy = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  const double denominator = sxx / dn + syy / dn + (mx - my) * (mx - my);
  return denominator > 0 ? 2 * (sxy / dn) / denominator : kNaN;
}

Agreement bland_altman(const std::vector<double>& est, const std::vector<double>& truth) {
  const std::size_t n = est.size();
  if (n < 2) return {kNaN, kNaN, kNaN};
  double mean = 0;
  for (std::size_t i = 0; i < n; ++i) mean += est[i] - truth[i];
  mean /= static_cast<double>(n);
  double ss = 0;
  for (std::size_t i = 0; i < n; ++i) ss += (est[i] - truth[i] - mean) * (est[i] - truth[i] - mean);
  const double sd = std::sqrt(ss / static_cast<double>(n - 1));
  return {mean, mean - 1.96 * sd, mean + 1.96 * sd};
}

SignedRankTest wilcoxon_signed_rank(const std::vector<double>& d) {
  std::vector<double> nz;
  for (double x : d) {
    if (x != 0 && std::isfinite(x)) nz.push_back(x);
  }
  SignedRankTest t;
  t.n = static_cast<int>(nz.size());
  if (t.n == 0) return t;
  // Ranks of |d|, ties sharing their mean rank; doubled so they stay integers.
  std::vector<std::size_t> order(nz.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return std::abs(nz[a]) < std::abs(nz[b]); });
  std::vector<int> rank2(nz.size());
  double tie_term = 0;  // sum of t^3 - t over tie groups
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j + 1 < order.size() && std::abs(nz[order[j + 1]]) == std::abs(nz[order[i]])) ++j;
    const int r2 = static_cast<int>(i + 1 + j + 1);  // 2 x mean rank of positions i..j (1-based)
    for (std::size_t k = i; k <= j; ++k) rank2[order[k]] = r2;
    const double g = static_cast<double>(j - i + 1);
    tie_term += g * g * g - g;
    i = j + 1;
  }
  int w2 = 0, total2 = 0;
  for (std::size_t i = 0; i < nz.size(); ++i) {
    total2 += rank2[i];
    if (nz[i] > 0) w2 += rank2[i];
  }
  t.w_plus = w2 / 2.0;
  const double n = t.n;
  if (t.n <= 50) {
    // Exact: each rank's sign is + or - with probability 1/2 under H0; count subsets
    // of the (doubled) ranks by their sum.
    std::vector<double> ways(static_cast<std::size_t>(total2) + 1, 0.0);
    ways[0] = 1;
    int reach = 0;
    for (int r : rank2) {
      for (int s = reach; s >= 0; --s) {
        if (ways[static_cast<std::size_t>(s)] != 0) ways[static_cast<std::size_t>(s + r)] += ways[static_cast<std::size_t>(s)];
      }
      reach += r;
    }
    const double all = std::ldexp(1.0, t.n);
    double lower = 0, upper = 0;
    for (int s = 0; s <= total2; ++s) {
      if (s <= w2) lower += ways[static_cast<std::size_t>(s)];
      if (s >= w2) upper += ways[static_cast<std::size_t>(s)];
    }
    t.p = std::min(1.0, 2 * std::min(lower, upper) / all);
  } else {
    const double mean = n * (n + 1) / 4;
    const double var = n * (n + 1) * (2 * n + 1) / 24 - tie_term / 48;
    const double z = (std::abs(t.w_plus - mean) - 0.5) / std::sqrt(var);
    t.p = std::min(1.0, 2 * (1 - normal_cdf(std::max(z, 0.0))));
  }
  return t;
}

PairedComparison compare_paired(const std::vector<double>& a, const std::vector<double>& b, std::uint64_t seed,
                                int resamples, double level) {
  PairedComparison c;
  const std::size_t n = std::min(a.size(), b.size());
  c.cases = static_cast<int>(n);
  std::vector<double> d(n);
  for (std::size_t i = 0; i < n; ++i) d[i] = a[i] - b[i];
  c.mean_difference = n > 0 ? std::accumulate(d.begin(), d.end(), 0.0) / static_cast<double>(n) : kNaN;
  c.test = wilcoxon_signed_rank(d);
  if (n < 3) {
    c.interval = {kNaN, kNaN};
    return c;
  }
  Rng rng(seed);
  std::vector<double> means;
  means.reserve(static_cast<std::size_t>(resamples));
  for (int r = 0; r < resamples; ++r) {
    double s = 0;
    for (std::size_t i = 0; i < n; ++i) s += d[static_cast<std::size_t>(rng.next() % n)];
    means.push_back(s / static_cast<double>(n));
  }
  c.interval = percentile_interval(means, level);
  return c;
}

LagCorrelation::LagCorrelation(std::vector<int> lags) : lags_(std::move(lags)), sums_(lags_.size()) {
  for (const int l : lags_)
    if (l <= 0) throw std::invalid_argument("LagCorrelation: lags must be positive");
  for (auto& s : sums_) s.fill(0);
}

void LagCorrelation::add(const std::vector<float>& map, int width, int height) {
  if (width <= 0 || height <= 0 || map.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw std::invalid_argument("LagCorrelation: the map is not width x height");
  for (std::size_t l = 0; l < lags_.size(); ++l) {
    auto& s = sums_[l];
    for (int y = 0; y < height; ++y) {
      const float* row = map.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
      for (int x = 0; x + lags_[l] < width; ++x) {
        const double a = row[x], b = row[x + lags_[l]];
        if (std::isnan(a) || std::isnan(b)) continue;
        s[0] += 1, s[1] += a, s[2] += b, s[3] += a * a, s[4] += b * b, s[5] += a * b;
      }
    }
  }
}

std::vector<double> LagCorrelation::correlations() const {
  std::vector<double> r;
  for (const auto& s : sums_) {
    const double n = s[0];
    const double vx = s[3] - s[1] * s[1] / n, vy = s[4] - s[2] * s[2] / n, cxy = s[5] - s[1] * s[2] / n;
    r.push_back(n >= 3 && vx > 0 && vy > 0 ? cxy / std::sqrt(vx * vy) : kNaN);
  }
  return r;
}

}  // namespace grapebench
