#include "bench/size_error.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <tuple>

namespace grapebench {

namespace {

struct Stats {
  int n = 0;
  double mean = 0, sd = 0;
};

Stats stats(const std::vector<double>& v) {
  Stats s;
  s.n = static_cast<int>(v.size());
  if (v.empty()) return s;
  for (double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  if (v.size() > 1) {
    double ss = 0;
    for (double x : v) ss += (x - s.mean) * (x - s.mean);
    s.sd = std::sqrt(ss / static_cast<double>(v.size() - 1));
  }
  return s;
}

}  // namespace

std::vector<SizeErrorCell> size_error_cells(const SceneSet& set, const std::vector<CaseResult>& cases,
                                            const SizeErrorParams& p) {
  // One measurement: a (case, frame, ROI kind, region) with both size rows.
  struct Pair {
    bool major = false, minor = false, ok = true;
    double err = 0, precision = 0;
  };
  // (estimator, roi) -> condition -> measurements, in a fixed order.
  std::map<std::pair<std::string, std::string>, std::map<int, std::vector<Pair>>> all;
  for (const auto& cr : cases) {
    std::map<std::tuple<std::string, std::string, int, int>, Pair> pairs;
    for (const auto& r : cr.rows) {
      if (r.roi.empty() || (r.quantity != "size_major" && r.quantity != "size_minor")) continue;
      Pair& pr = pairs[{r.estimator, r.roi, r.frame, r.region}];
      const bool major = r.quantity == "size_major";
      (major ? pr.major : pr.minor) = true;
      pr.ok = pr.ok && r.ok;
      if (r.ok) pr.err += (major ? p.weights[0] : p.weights[1]) * std::abs(r.estimate - r.truth);  // Eq. 3
      pr.precision = r.region_precision;
    }
    for (const auto& [key, pr] : pairs) {
      if (!pr.major || !pr.minor) continue;
      all[{std::get<0>(key), std::get<1>(key)}][cr.condition].push_back(pr);
    }
  }
  std::vector<SizeErrorCell> out;
  const auto cell = [&](const std::string& est, const std::string& roi, int condition, const std::vector<Pair>& ms) {
    SizeErrorCell c;
    c.estimator = est;
    c.roi = roi;
    c.condition = condition;
    std::vector<double> errs, kept;
    double prec = 0;
    for (const auto& m : ms) {
      if (!m.ok) {
        ++c.failed;
        continue;
      }
      errs.push_back(m.err);
      prec += m.precision;
      if (m.err < p.filter) kept.push_back(m.err);
    }
    const Stats a = stats(errs), k = stats(kept);
    c.regions = a.n;
    c.mean = a.mean;
    c.sd = a.sd;
    c.kept = k.n;
    c.kept_mean = k.mean;
    c.kept_sd = k.sd;
    c.precision_mean = a.n ? prec / a.n : 0;
    return c;
  };
  for (const auto& [key, by_condition] : all) {
    std::vector<Pair> pooled;
    for (const auto& [c, ms] : by_condition) pooled.insert(pooled.end(), ms.begin(), ms.end());
    out.push_back(cell(key.first, key.second, -1, pooled));
  }
  for (std::size_t c = 0; c < set.conditions.size(); ++c) {
    for (const auto& [key, by_condition] : all) {
      const auto it = by_condition.find(static_cast<int>(c));
      out.push_back(cell(key.first, key.second, static_cast<int>(c), it == by_condition.end() ? std::vector<Pair>{} : it->second));
    }
  }
  return out;
}

std::string size_error_entry(const SizeErrorCell& c, bool filtered) {
  const int n = filtered ? c.kept : c.regions;
  if (n == 0) return "-";
  char b[96];
  std::snprintf(b, sizeof b, "%.1f +- %.1f (%d)", 100 * (filtered ? c.kept_mean : c.mean), 100 * (filtered ? c.kept_sd : c.sd), n);
  return b;
}

std::string size_error_table(const std::vector<SizeErrorCell>& cells) {
  const std::vector<std::string> kinds = {"auto_r", "auto_cm", "manual_r", "manual_cm"};
  std::vector<std::string> estimators, present;
  for (const auto& c : cells) {
    if (c.condition != -1) continue;
    if (std::find(estimators.begin(), estimators.end(), c.estimator) == estimators.end()) estimators.push_back(c.estimator);
    if (std::find(present.begin(), present.end(), c.roi) == present.end()) present.push_back(c.roi);
  }
  if (estimators.empty()) return "";
  std::vector<std::string> cols;
  for (const auto& k : kinds) {
    if (std::find(present.begin(), present.end(), k) != present.end()) cols.push_back(k);
  }
  std::ostringstream s;
  s << "| estimator | |";
  for (const auto& k : cols) s << " " << k << " |";
  s << "\n|---|---|";
  for (std::size_t i = 0; i < cols.size(); ++i) s << "---|";
  s << "\n";
  for (const auto& e : estimators) {
    for (int filtered = 0; filtered < 2; ++filtered) {
      s << "| " << (filtered ? "" : e) << " | " << (filtered ? "Filter" : "All") << " |";
      for (const auto& k : cols) {
        const SizeErrorCell* c = nullptr;
        for (const auto& x : cells) {
          if (x.condition == -1 && x.estimator == e && x.roi == k) c = &x;
        }
        s << " " << (c ? size_error_entry(*c, filtered != 0) : "-") << " |";
      }
      s << "\n";
    }
  }
  return s.str();
}

std::string size_error_csv(const SceneSet& set, const std::vector<SizeErrorCell>& cells) {
  std::ostringstream s;
  s << "condition,estimator,roi,regions,failed,err_mean_cm,err_sd_cm,kept,kept_mean_cm,kept_sd_cm,precision_mean\n";
  char b[256];
  for (const auto& c : cells) {
    const std::string cond = c.condition < 0 ? "all" : set.conditions[static_cast<std::size_t>(c.condition)].label;
    std::snprintf(b, sizeof b, ",%d,%d,%.6g,%.6g,%d,%.6g,%.6g,%.6g\n", c.regions, c.failed, 100 * c.mean, 100 * c.sd,
                  c.kept, 100 * c.kept_mean, 100 * c.kept_sd, c.precision_mean);
    s << "\"" << cond << "\"," << c.estimator << "," << c.roi << b;
  }
  return s.str();
}

}  // namespace grapebench
