#include "bench/check.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

namespace grapebench {

namespace {

using Key = std::tuple<std::string, std::string, std::string>;

std::map<Key, nlohmann::json> rows_of(const nlohmann::json& summary) {
  std::map<Key, nlohmann::json> m;
  for (const auto& r : summary.at("scores")) {
    m[{r.at("condition").get<std::string>(), r.at("estimator").get<std::string>(), r.at("quantity").get<std::string>()}] = r;
  }
  return m;
}

double value(const nlohmann::json& r, const char* k) {
  const auto it = r.find(k);
  return it == r.end() || it->is_null() ? std::nan("") : it->get<double>();
}

std::string name(const Key& k) {
  const auto& [c, e, q] = k;
  return (c.empty() ? "" : "[" + c + "] ") + e + " " + q;
}

}  // namespace

CheckResult check_against_baseline(const nlohmann::json& run, const nlohmann::json& baseline) {
  Tolerances t;
  if (baseline.contains("tolerances")) {
    const auto& j = baseline["tolerances"];
    t.rmse_rel = j.value("rmse_rel", t.rmse_rel);
    t.rmse_abs = j.value("rmse_abs", t.rmse_abs);
    t.mape_pct_abs = j.value("mape_pct_abs", t.mape_pct_abs);
    t.r2_abs = j.value("r2_abs", t.r2_abs);
    t.bias_rmse_frac = j.value("bias_rmse_frac", t.bias_rmse_frac);
    t.success_rate_abs = j.value("success_rate_abs", t.success_rate_abs);
  }
  const auto now = rows_of(run), base = rows_of(baseline);
  CheckResult res;
  std::ostringstream d;
  char line[400];
  for (const auto& [key, b] : base) {
    const auto it = now.find(key);
    if (it == now.end()) {
      res.pass = false;
      d << "MISSING  " << name(key) << ": in the baseline, not in this run\n";
      continue;
    }
    ++res.rows_compared;
    const auto& r = it->second;
    const std::string unit = b.value("unit", "");
    const auto report = [&](const char* metric, double was, double is, double allowed) {
      res.pass = false;
      std::snprintf(line, sizeof line, "WORSE    %s: %s %.6g -> %.6g %s (allowed %.6g)\n", name(key).c_str(), metric, was,
                    is, unit.c_str(), allowed);
      d << line;
    };
    const double rb = value(b, "rmse"), rn = value(r, "rmse");
    const bool rmse_missing = std::isfinite(rb) && !std::isfinite(rn);
    if (rmse_missing || (std::isfinite(rb) && rn > rb * (1 + t.rmse_rel) + t.rmse_abs)) {
      report("RMSE", rb, rn, rb * (1 + t.rmse_rel) + t.rmse_abs);
    }
    const double mb = value(b, "mape_pct"), mn = value(r, "mape_pct");
    if (std::isfinite(mb) && (!std::isfinite(mn) || mn > mb + t.mape_pct_abs)) report("MAPE %", mb, mn, mb + t.mape_pct_abs);
    const double r2b = value(b, "r2"), r2n = value(r, "r2");
    if (std::isfinite(r2b) && (!std::isfinite(r2n) || r2n < r2b - t.r2_abs)) report("R2", r2b, r2n, r2b - t.r2_abs);
    const double bb = value(b, "bias"), bn = value(r, "bias");
    if (std::isfinite(bb) && std::isfinite(rb) &&
        (!std::isfinite(bn) || std::abs(bn) > std::abs(bb) + t.bias_rmse_frac * rb + t.rmse_abs)) {
      report("|bias|", std::abs(bb), std::abs(bn), std::abs(bb) + t.bias_rmse_frac * rb + t.rmse_abs);
    }
    const double sb = value(b, "success_rate"), sn = value(r, "success_rate");
    if (std::isfinite(sb) && (!std::isfinite(sn) || sn < sb - t.success_rate_abs - 1e-12)) {
      report("success rate", sb, sn, sb - t.success_rate_abs);
    }
  }
  for (const auto& [key, r] : now) {
    if (!base.count(key)) d << "NEW      " << name(key) << ": not in the baseline (not checked)\n";
  }
  res.diff = d.str();
  return res;
}

}  // namespace grapebench
