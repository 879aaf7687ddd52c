// `grapebench compare-bench`: two Google Benchmark JSON files (same machine, run with
// --benchmark_repetitions and --benchmark_enable_random_interleaving), flagged by the
// ratio of medians the way Google Benchmark's compare.py does.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace grapebench {

struct BenchComparison {
  bool slower = false;   // some benchmark slowed beyond the threshold
  std::string table;     // one line per benchmark: medians, ratio, U-test p-value, verdict
};

// Google Benchmark writes the counters' undefined aggregates (the cv of a counter that
// is 0 in every repetition) as bare NaN or Infinity, which JSON does not have: those
// tokens outside strings become null.
std::string benchmark_json_text(std::string text);

// A benchmark is flagged when median(new) / median(old) > 1 + threshold and the
// two-sided Mann-Whitney U test gives p < alpha; with fewer than 3 repetitions on a
// side it gets no verdict. Aggregate rows (mean/median/stddev) and repetitions with
// `error_occurred` are ignored; an entry without `time_unit` is an error. Errors name
// the file by `baseline_name` or `contender_name`.
BenchComparison compare_benchmarks(const nlohmann::json& baseline, const nlohmann::json& contender, double threshold,
                                   double alpha = 0.05, const std::string& baseline_name = "baseline",
                                   const std::string& contender_name = "contender");

// The speed gate: in-run ratios of medians (a grapebench operation over its reference
// measured in the same run: the raw Embree loop, Open3D), each under a stated bound.
// `gate`: {"format": "grapebench-speed-gate-1", "ratios": [{"name", "numerator",
// "denominator", "max"}]} naming benchmarks (run_name) of `runs`, Google Benchmark
// JSON files (file name, content). Throws InputError naming the file (`gate_name`) and key of a malformed
// gate, or a benchmark no run holds.
struct SpeedGateResult {
  bool pass = true;
  std::string table;  // one line per ratio: medians, ratio, bound, verdict
};
SpeedGateResult check_speed_gate(const nlohmann::json& gate, const std::string& gate_name,
                                 const std::vector<std::pair<std::string, nlohmann::json>>& runs);

}  // namespace grapebench
