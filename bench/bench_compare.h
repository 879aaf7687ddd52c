// `grapebench compare-bench`: two Google Benchmark JSON files (same machine, run with
// --benchmark_repetitions and --benchmark_enable_random_interleaving), flagged by the
// ratio of medians the way Google Benchmark's compare.py does.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace grapebench {

struct BenchComparison {
  bool slower = false;   // some benchmark slowed beyond the threshold
  std::string table;     // one line per benchmark: medians, ratio, U-test p-value, verdict
};

// A benchmark is flagged when median(new) / median(old) > 1 + threshold and, with at
// least 3 repetitions on each side, the two-sided Mann-Whitney U test gives p < alpha.
// Aggregate rows (mean/median/stddev) are ignored; the repetitions are used.
BenchComparison compare_benchmarks(const nlohmann::json& baseline, const nlohmann::json& contender, double threshold,
                                   double alpha = 0.05);

}  // namespace grapebench
