#include "bench/bench_compare.h"

#include "synth/config.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <vector>

namespace grapebench {

namespace {

std::map<std::string, std::vector<double>> times_of(const nlohmann::json& benchmarks) {
  std::map<std::string, std::vector<double>> out;
  for (const auto& b : benchmarks) {
    if (b.value("run_type", "iteration") != "iteration") continue;
    const std::string name = b.value("run_name", b.at("name").get<std::string>());
    const std::string unit = b.value("time_unit", "ns");
    if (unit != "s" && unit != "ms" && unit != "us" && unit != "ns") {
      throw InputError("benchmark '" + name + "': time_unit '" + unit + "' (s, ms, us or ns)");
    }
    const double scale = unit == "s" ? 1e9 : unit == "ms" ? 1e6 : unit == "us" ? 1e3 : 1.0;
    const double t = b.at("real_time").get<double>();
    if (!std::isfinite(t) || t <= 0) {
      throw InputError("benchmark '" + name + "': real_time " + std::to_string(t) + " (a positive, finite time)");
    }
    out[name].push_back(t * scale);  // ns
  }
  return out;
}

std::map<std::string, std::vector<double>> times(const nlohmann::json& j, const char* which) {
  if (!j.is_object() || !j.contains("benchmarks") || !j["benchmarks"].is_array() || j["benchmarks"].empty())
    throw InputError(std::string(which) + ": not Google Benchmark JSON ('benchmarks' must be a non-empty list)");
  try {
    return times_of(j["benchmarks"]);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string(which) + ": a benchmark entry is malformed (" + e.what() + ")");
  }
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Two-sided Mann-Whitney U test, normal approximation with tie correction.
double u_test_p(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<std::pair<double, int>> all;
  for (double x : a) all.emplace_back(x, 0);
  for (double x : b) all.emplace_back(x, 1);
  std::sort(all.begin(), all.end());
  const double n1 = static_cast<double>(a.size()), n2 = static_cast<double>(b.size()), n = n1 + n2;
  double rank_a = 0, ties = 0;
  for (std::size_t i = 0; i < all.size();) {
    std::size_t j = i;
    while (j < all.size() && all[j].first == all[i].first) ++j;
    const double r = 0.5 * static_cast<double>(i + 1 + j);  // mean rank of the tie group
    const double t = static_cast<double>(j - i);
    ties += t * t * t - t;
    for (std::size_t k = i; k < j; ++k) {
      if (all[k].second == 0) rank_a += r;
    }
    i = j;
  }
  const double u = rank_a - n1 * (n1 + 1) / 2;
  const double mu = n1 * n2 / 2;
  const double sigma = std::sqrt(n1 * n2 / 12 * ((n + 1) - ties / (n * (n - 1))));
  if (sigma <= 0) return 1;
  const double z = (std::abs(u - mu) - 0.5) / sigma;
  return std::erfc(std::max(z, 0.0) / std::sqrt(2.0));
}

}  // namespace

BenchComparison compare_benchmarks(const nlohmann::json& baseline, const nlohmann::json& contender, double threshold,
                                   double alpha) {
  const auto old_t = times(baseline, "baseline"), new_t = times(contender, "contender");
  BenchComparison c;
  std::ostringstream s;
  char line[300];
  std::snprintf(line, sizeof line, "%-40s %12s %12s %8s %8s  %s\n", "benchmark", "old median", "new median", "ratio",
                "p", "verdict");
  s << line;
  for (const auto& [name, nt] : new_t) {
    const auto it = old_t.find(name);
    if (it == old_t.end()) {
      std::snprintf(line, sizeof line, "%-40s %12s %12.4g %8s %8s  new\n", name.c_str(), "-", median(nt) / 1e6, "-", "-");
      s << line;
      continue;
    }
    const double mo = median(it->second), mn = median(nt), ratio = mn / mo;
    const bool enough = it->second.size() >= 3 && nt.size() >= 3;
    const double p = enough ? u_test_p(it->second, nt) : std::nan("");
    const bool flagged = ratio > 1 + threshold && (!enough || p < alpha);
    const bool faster = ratio < 1 - threshold && (!enough || p < alpha);
    c.slower = c.slower || flagged;
    std::snprintf(line, sizeof line, "%-40s %10.4g ms %10.4g ms %8.3f %8.3g  %s\n", name.c_str(), mo / 1e6, mn / 1e6,
                  ratio, p, flagged ? "SLOWER" : faster ? "faster" : "same");
    s << line;
  }
  for (const auto& [name, ot] : old_t) {
    if (!new_t.count(name)) s << name << ": only in the baseline\n";
  }
  c.table = s.str();
  return c;
}

}  // namespace grapebench
