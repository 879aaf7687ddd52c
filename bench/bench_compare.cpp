#include "bench/bench_compare.h"

#include "synth/config.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string_view>
#include <vector>

namespace grapebench {

namespace {

std::map<std::string, std::vector<double>> times_of(const nlohmann::json& benchmarks) {
  std::map<std::string, std::vector<double>> out;
  for (const auto& b : benchmarks) {
    if (b.value("run_type", "iteration") != "iteration") continue;
    // A repetition that failed (state.SkipWithError) has no meaningful time.
    if (b.value("error_occurred", false)) continue;
    const std::string name = b.value("run_name", b.at("name").get<std::string>());
    // Google Benchmark always writes the unit; read as ns when absent, a file in ms
    // read 1e6 times too fast (a 44 % slowdown came out faster).
    if (!b.contains("time_unit")) throw InputError("benchmark '" + name + "': no time_unit (s, ms, us or ns)");
    const std::string unit = b.at("time_unit").get<std::string>();
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
  } catch (const InputError& e) {
    throw InputError(std::string(which) + ": " + e.what());
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

std::string benchmark_json_text(std::string text) {
  std::string out;
  out.reserve(text.size());
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    if (in_string) {
      out += ch;
      if (ch == '\\' && i + 1 < text.size()) out += text[++i];
      else if (ch == '"') in_string = false;
      continue;
    }
    if (ch == '"') in_string = true;
    bool replaced = false;
    for (const std::string_view token : {"-Infinity", "Infinity", "NaN", "-NaN"}) {
      if (text.compare(i, token.size(), token) == 0) {
        out += "null";
        i += token.size() - 1;
        replaced = true;
        break;
      }
    }
    if (!replaced) out += ch;
  }
  return out;
}

BenchComparison compare_benchmarks(const nlohmann::json& baseline, const nlohmann::json& contender, double threshold,
                                   double alpha, const std::string& baseline_name, const std::string& contender_name) {
  const auto old_t = times(baseline, baseline_name.c_str()), new_t = times(contender, contender_name.c_str());
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
    // Under 3 repetitions a side the U test cannot say anything: no verdict, rather
    // than a SLOWER on one noisy sample.
    const bool flagged = enough && ratio > 1 + threshold && p < alpha;
    const bool faster = enough && ratio < 1 - threshold && p < alpha;
    c.slower = c.slower || flagged;
    std::snprintf(line, sizeof line, "%-40s %10.4g ms %10.4g ms %8.3f %8.3g  %s\n", name.c_str(), mo / 1e6, mn / 1e6,
                  ratio, p, !enough ? "? (under 3 repetitions)" : flagged ? "SLOWER" : faster ? "faster" : "same");
    s << line;
  }
  for (const auto& [name, ot] : old_t) {
    if (!new_t.count(name)) s << name << ": only in the baseline\n";
  }
  c.table = s.str();
  return c;
}

SpeedGateResult check_speed_gate(const nlohmann::json& gate, const std::string& gate_name,
                                 const std::vector<std::pair<std::string, nlohmann::json>>& runs) {
  const auto fail = [&](const std::string& what) { throw InputError(gate_name + ": " + what); };
  if (!gate.is_object() || !gate.contains("format") || gate["format"] != "grapebench-speed-gate-1")
    fail("not a speed gate ('format' must be \"grapebench-speed-gate-1\")");
  if (!gate.contains("ratios") || !gate["ratios"].is_array() || gate["ratios"].empty())
    fail("'ratios' must be a non-empty list");
  std::map<std::string, std::vector<double>> t;
  for (const auto& [file, run] : runs) {
    for (auto& [name, v] : times(run, file.c_str())) t[name].insert(t[name].end(), v.begin(), v.end());
  }
  SpeedGateResult r;
  std::ostringstream s;
  char line[400];
  std::snprintf(line, sizeof line, "%-44s %12s %12s %7s %6s %5s  %s\n", "ratio", "grapebench", "reference", "ratio",
                "max", "runs", "verdict");
  s << line;
  for (std::size_t k = 0; k < gate["ratios"].size(); ++k) {
    const nlohmann::json& g = gate["ratios"][k];
    const std::string where = "ratios[" + std::to_string(k) + "]";
    for (const char* key : {"name", "numerator", "denominator"})
      if (!g.is_object() || !g.contains(key) || !g[key].is_string()) fail(where + "." + key + ": a string is required");
    if (!g.contains("max") || !g["max"].is_number() || !(g["max"].get<double>() > 0 && g["max"].get<double>() <= 100))
      fail(where + ".max: a number in (0, 100] is required");
    for (const auto& [key, value] : g.items())
      if (key != "name" && key != "numerator" && key != "denominator" && key != "max") fail(where + "." + key + ": unknown key");
    const std::string num = g["numerator"], den = g["denominator"];
    for (const std::string& b : {num, den})
      if (!t.count(b)) fail(where + ": no run holds benchmark '" + b + "'");
    const double mn = median(t[num]), md = median(t[den]), ratio = mn / md, bound = g["max"].get<double>();
    const bool ok = ratio <= bound;
    r.pass = r.pass && ok;
    std::snprintf(line, sizeof line, "%-44s %9.4g ms %9.4g ms %7.3f %6.2f %5zu  %s\n", g["name"].get<std::string>().c_str(),
                  mn / 1e6, md / 1e6, ratio, bound, std::min(t[num].size(), t[den].size()), ok ? "ok" : "TOO SLOW");
    s << line;
  }
  r.table = s.str();
  return r;
}

}  // namespace grapebench
