#include "bench/check.h"

#include "synth/config.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <sstream>
#include <vector>

namespace grapebench {

namespace {

using Key = std::tuple<std::string, std::string, std::string>;

// The rows of a summary, checked: a `scene` name, a non-empty `scores` list of
// objects with string keys and numeric (or null) metrics, each key once.
std::map<Key, nlohmann::json> rows_of(const nlohmann::json& summary, const std::string& what) {
  const auto bad = [&](const std::string& why) { throw InputError(what + ": " + why); };
  if (!summary.is_object()) bad("not a summary (a JSON object with `scene` and `scores`)");
  if (!summary.contains("scene") || !summary["scene"].is_string()) bad("'scene' must be the scene's name");
  if (!summary.contains("scores") || !summary["scores"].is_array()) bad("'scores' must be a list of rows");
  const bool other_rows = (summary.contains("classification") && summary["classification"].is_array() &&
                           !summary["classification"].empty()) ||
                          (summary.contains("stereo") && summary["stereo"].is_object());
  if (summary["scores"].empty() && !other_rows) bad("'scores' is empty: nothing to compare");
  std::map<Key, nlohmann::json> m;
  int i = 0;
  for (const auto& r : summary["scores"]) {
    const std::string at = "'scores[" + std::to_string(i++) + "]";
    if (!r.is_object()) bad(at + "' must be an object");
    for (const char* k : {"condition", "estimator", "quantity"})
      if (!r.contains(k) || !r[k].is_string()) bad(at + "." + k + "' must be a string");
    if (r.contains("unit") && !r["unit"].is_string()) bad(at + ".unit' must be a string");
    for (const char* k : {"rmse", "mape_pct", "r2", "bias", "success_rate"})
      if (r.contains(k) && !r[k].is_number() && !r[k].is_null()) bad(at + "." + k + "' must be a number or null");
    const Key key{r["condition"].get<std::string>(), r["estimator"].get<std::string>(), r["quantity"].get<std::string>()};
    if (!m.emplace(key, r).second) bad(at + "' repeats the row of " + std::get<1>(key) + " " + std::get<2>(key));
  }
  return m;
}

// The rows of an optional list `path` (e.g. "classification", "stereo.depth"), keyed
// by the string or integer fields `keys`, each row once; the numeric fields `metrics`
// numbers or null. Absent section: no rows.
std::map<std::string, nlohmann::json> table_of(const nlohmann::json& summary, const std::string& path,
                                               const std::vector<const char*>& keys,
                                               const std::vector<const char*>& metrics, const std::string& what) {
  const auto bad = [&](const std::string& why) { throw InputError(what + ": " + why); };
  const nlohmann::json* list = &summary;
  std::string at;
  for (std::size_t b = 0, e; b <= path.size(); b = e + 1) {
    e = path.find('.', b);
    if (e == std::string::npos) e = path.size();
    const std::string part = path.substr(b, e - b);
    if (!list->is_object() || !list->contains(part)) return {};
    list = &(*list)[part];
  }
  if (!list->is_array()) bad("'" + path + "' must be a list of rows");
  std::map<std::string, nlohmann::json> m;
  int i = 0;
  for (const auto& r : *list) {
    at = "'" + path + "[" + std::to_string(i++) + "]";
    if (!r.is_object()) bad(at + "' must be an object");
    std::string key;
    for (const char* k : keys) {
      if (!r.contains(k) || !(r[k].is_string() || r[k].is_number_integer())) bad(at + "." + k + "' must be a string or an integer");
      key += (key.empty() ? "" : " ") + (r[k].is_string() ? r[k].get<std::string>() : std::to_string(r[k].get<long long>()));
    }
    for (const char* k : metrics)
      if (r.contains(k) && !r[k].is_number() && !r[k].is_null()) bad(at + "." + k + "' must be a number or null");
    if (!m.emplace(key, r).second) bad(at + "' repeats the row of " + key);
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

CheckResult check_against_baseline(const nlohmann::json& run, const nlohmann::json& baseline,
                                   const std::string& run_name, const std::string& baseline_name) {
  const auto now = rows_of(run, run_name), base = rows_of(baseline, baseline_name);
  if (run["scene"] != baseline["scene"]) {
    throw InputError(run_name + " is a run of scene '" + run["scene"].get<std::string>() + "', " + baseline_name +
                     " a baseline of '" + baseline["scene"].get<std::string>() + "'");
  }
  Tolerances t;
  if (baseline.contains("tolerances")) {
    const auto& j = baseline["tolerances"];
    if (!j.is_object()) throw InputError(baseline_name + ": 'tolerances' must be an object of numbers");
    // Each with its largest sensible value: a tolerance of 1e308 would pass anything.
    struct Known {
      double* value;
      double max;
      const char* unit;
    };
    const std::map<std::string, Known> known = {
        {"rmse_rel", {&t.rmse_rel, 10, "fraction of the baseline's RMSE"}},
        {"rmse_abs", {&t.rmse_abs, 1e4, "cm3 or mm"}},
        {"mape_pct_abs", {&t.mape_pct_abs, 1000, "percentage points"}},
        {"r2_abs", {&t.r2_abs, 100, "-"}},
        {"bias_rmse_frac", {&t.bias_rmse_frac, 10, "fraction of the baseline's RMSE"}},
        {"success_rate_abs", {&t.success_rate_abs, 1, "rate"}},
        {"classification_abs", {&t.classification_abs, 1, "AUC, IoU or F1"}},
        {"stereo_rate_abs", {&t.stereo_rate_abs, 1, "rate"}},
        {"cut_error_mm_abs", {&t.cut_error_mm_abs, 1000, "mm"}}};
    for (const auto& [k, v] : j.items()) {
      if (!known.count(k)) {
        std::string names;
        for (const auto& n : known) names += (names.empty() ? "" : ", ") + n.first;
        throw InputError(baseline_name + ": 'tolerances." + k + "' is not a tolerance (one of: " + names + ")");
      }
      const Known& to = known.at(k);
      if (!v.is_number() || !(v.get<double>() >= 0 && v.get<double>() <= to.max)) {
        char range[120];
        std::snprintf(range, sizeof range, "must be a number in [0, %g] (%s)", to.max, to.unit);
        throw InputError(baseline_name + ": 'tolerances." + k + "' " + range + ", got " + v.dump());
      }
      *to.value = v.get<double>();
    }
  }
  CheckResult res;
  std::ostringstream d;
  char line[400];
  for (const auto& row : base) {
    const Key& key = row.first;  // not a structured binding: the lambda below captures it (clang 14)
    const nlohmann::json& b = row.second;
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
      // The row's unit belongs to RMSE and bias only (MAPE is in %, R2 and rates are pure).
      const bool in_unit = metric == std::string("RMSE") || metric == std::string("|bias|");
      std::snprintf(line, sizeof line, "WORSE    %s: %s %.6g -> %.6g%s%s (allowed %.6g)\n", name(key).c_str(), metric, was,
                    is, in_unit && !unit.empty() ? " " : "", in_unit ? unit.c_str() : "", allowed);
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
  // The other sections: each metric may worsen by its tolerance (sign +1: higher is
  // better), a missing row or value is a regression.
  struct Metric {
    const char* field;
    int sign;
    double allowed;
    const char* unit;
  };
  const auto compare_table = [&](const std::string& path, const std::vector<const char*>& keys,
                                 const std::function<std::vector<Metric>(const nlohmann::json&)>& metrics_of) {
    std::vector<const char*> fields;
    for (const Metric& m : metrics_of(nlohmann::json::object())) fields.push_back(m.field);
    const auto b_rows = table_of(baseline, path, keys, fields, baseline_name);
    const auto n_rows = table_of(run, path, keys, fields, run_name);
    for (const auto& [key, b] : b_rows) {
      const auto it = n_rows.find(key);
      if (it == n_rows.end()) {
        res.pass = false;
        d << "MISSING  " << path << " " << key << ": in the baseline, not in this run\n";
        continue;
      }
      ++res.rows_compared;
      for (const Metric& m : metrics_of(b)) {
        const double was = value(b, m.field), is = value(it->second, m.field);
        if (!std::isfinite(was)) continue;
        const double limit = was - m.sign * m.allowed;
        if (!std::isfinite(is) || m.sign * (is - limit) < -1e-12) {
          res.pass = false;
          std::snprintf(line, sizeof line, "WORSE    %s %s: %s %.6g -> %.6g%s%s (allowed %.6g)\n", path.c_str(),
                        key.c_str(), m.field, was, is, *m.unit ? " " : "", m.unit, limit);
          d << line;
        }
      }
    }
    for (const auto& [key, r] : n_rows)
      if (!b_rows.count(key)) d << "NEW      " << path << " " << key << ": not in the baseline (not checked)\n";
  };
  compare_table("classification", {"condition", "estimator", "quantity"}, [&](const nlohmann::json& b) {
    // A row key may be an integer (rows_of): compared, never read as a string (found by
    // tests/fuzz/baseline_fuzz.cpp: a quantity of 7516688919 ended `check` with exit 3).
    const bool lower_better = b.contains("quantity") && b["quantity"] == "berry_fpr";
    return std::vector<Metric>{{"mean", lower_better ? -1 : 1, t.classification_abs, ""}};
  });
  compare_table("stereo.cut_success", {"condition", "estimator"}, [&](const nlohmann::json&) {
    return std::vector<Metric>{{"rate", 1, t.stereo_rate_abs, ""}};
  });
  compare_table("stereo.depth", {"estimator", "depth_mm"}, [&](const nlohmann::json&) {
    return std::vector<Metric>{{"found_rate", 1, t.stereo_rate_abs, ""},
                               {"ez_mm", -1, t.cut_error_mm_abs, "mm"},
                               {"ex_mm", -1, t.cut_error_mm_abs, "mm"}};
  });
  res.diff = d.str();
  return res;
}

}  // namespace grapebench
