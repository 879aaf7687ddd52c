#include "bench/scoring/scalars.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace grapebench {

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const auto hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

Score score(const std::vector<double>& est, const std::vector<double>& truth, int cases,
            const std::vector<double>& seconds) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Score s;
  s.cases = cases;
  s.succeeded = static_cast<int>(est.size());
  s.success_rate = cases > 0 ? static_cast<double>(s.succeeded) / cases : nan;
  s.time_median = quantile(seconds, 0.5);
  s.time_p25 = quantile(seconds, 0.25);
  s.time_p75 = quantile(seconds, 0.75);
  const std::size_t n = est.size();
  if (n == 0) {
    s.r2 = s.r2_identity = s.rmse = s.mae = s.bias = s.mape = s.slope = s.intercept = nan;
    return s;
  }
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) {
    mx += truth[i];
    my += est[i];
  }
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double sxx = 0, syy = 0, sxy = 0, se2 = 0, sae = 0, sb = 0, sape = 0, sst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = truth[i] - mx, dy = est[i] - my, e = est[i] - truth[i];
    sxx += dx * dx;
    syy += dy * dy;
    sxy += dx * dy;
    se2 += e * e;
    sae += std::abs(e);
    sb += e;
    sape += truth[i] != 0 ? std::abs(e / truth[i]) : nan;
    sst += dx * dx;
  }
  const double dn = static_cast<double>(n);
  s.rmse = std::sqrt(se2 / dn);
  s.mae = sae / dn;
  s.bias = sb / dn;
  s.mape = 100 * sape / dn;
  if (sxx > 0 && syy > 0) {
    s.r2 = sxy * sxy / (sxx * syy);
  } else {
    s.r2 = nan;
  }
  s.r2_identity = sst > 0 ? 1 - se2 / sst : nan;
  if (sxx > 0) {
    s.slope = sxy / sxx;
    s.intercept = my - s.slope * mx;
  } else {
    s.slope = s.intercept = nan;
  }
  return s;
}

namespace {

// Quantities that are not lengths: (name, unit, scale from the stored value).
struct Unit {
  const char* quantity;
  const char* unit;
  double scale;
};
constexpr Unit kUnits[] = {
    {"volume", "cm3", 1e6},        {"envelope_volume", "cm3", 1e6}, {"cut_success", "-", 1},
    {"berries_found", "count", 1}, {"berry_precision", "-", 1},     {"berry_centre_error", "px", 1},
    {"berry_radius_error", "px", 1}, {"berry_count", "count", 1},  {"instances", "count", 1},
    {"cluster_iou", "-", 1},       {"cluster_top_px", "px", 1},
    // Seed 004's classification rows (fractions).
    {"accuracy", "-", 1},          {"miou", "-", 1},                {"berry_tpr", "-", 1},
    {"berry_fpr", "-", 1},
    // A failed case's row per estimator (bench/protocols/capture.cpp): no value.
    {"case", "-", 1},
};
// Per-class classification rows: auc_berry, iou_leaf, ... (fractions).
constexpr const char* kFractionPrefixes[] = {"auc_", "iou_", "precision_", "recall_"};

bool is_fraction_row(const std::string& q) {
  for (const char* p : kFractionPrefixes) {
    if (q.rfind(p, 0) == 0) return true;
  }
  return false;
}

}  // namespace

const char* display_unit(const std::string& q) {
  if (is_fraction_row(q)) return "-";
  for (const Unit& u : kUnits) {
    if (q == u.quantity) return u.unit;
  }
  return "mm";
}
double display_scale(const std::string& q) {
  if (is_fraction_row(q)) return 1;
  for (const Unit& u : kUnits) {
    if (q == u.quantity) return u.scale;
  }
  return 1e3;
}

}  // namespace grapebench
