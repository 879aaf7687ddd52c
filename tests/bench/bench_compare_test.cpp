// compare-bench's and the speed gate's reading of Google Benchmark JSON: ratios of
// in-run medians against their bounds, a deliberate slowdown caught, malformed gates
// and Google Benchmark's bare NaN handled.
#include "bench/bench_compare.h"

#include <gtest/gtest.h>

#include "synth/config.h"

namespace grapebench {
namespace {

// Google Benchmark JSON: `reps` repetitions of each (name, ms) with 2 % spread, and
// the aggregate rows it writes beside them (ignored).
nlohmann::json run_of(const std::vector<std::pair<std::string, double>>& times, int reps = 5) {
  nlohmann::json j = {{"context", nlohmann::json::object()}, {"benchmarks", nlohmann::json::array()}};
  for (int r = 0; r < reps; ++r) {
    for (const auto& [name, ms] : times) {
      j["benchmarks"].push_back({{"name", name}, {"run_name", name}, {"run_type", "iteration"},
                                 {"real_time", ms * (1 + 0.01 * (r % 3 - 1))}, {"time_unit", "ms"}});
    }
  }
  for (const auto& [name, ms] : times)
    j["benchmarks"].push_back({{"name", name + "_median"}, {"run_name", name}, {"run_type", "aggregate"},
                               {"real_time", ms}, {"time_unit", "ms"}});
  return j;
}

nlohmann::json gate_of(double max) {
  return {{"format", "grapebench-speed-gate-1"},
          {"ratios", {{{"name", "model / raw"}, {"numerator", "BM_model"}, {"denominator", "BM_raw"}, {"max", max}}}}};
}

TEST(SpeedGate, PassesUnderItsBoundAndFailsADeliberateSlowdown) {
  const auto ok = check_speed_gate(gate_of(1.25), "gate.json", {{"a.json", run_of({{"BM_model", 11}, {"BM_raw", 10}})}});
  EXPECT_TRUE(ok.pass) << ok.table;
  EXPECT_NE(ok.table.find("1.100"), std::string::npos) << ok.table;
  // The model made 30 % slower, the reference unchanged.
  const auto slow = check_speed_gate(gate_of(1.25), "gate.json", {{"a.json", run_of({{"BM_model", 14.3}, {"BM_raw", 10}})}});
  EXPECT_FALSE(slow.pass);
  EXPECT_NE(slow.table.find("TOO SLOW"), std::string::npos) << slow.table;
  // The two sides may come from two files of one run.
  const auto split = check_speed_gate(gate_of(1.25), "gate.json",
                                      {{"a.json", run_of({{"BM_model", 11}})}, {"b.json", run_of({{"BM_raw", 10}})}});
  EXPECT_TRUE(split.pass);
}

TEST(SpeedGate, MalformedGatesAndMissingBenchmarksNameTheKey) {
  const std::vector<std::pair<std::string, nlohmann::json>> runs = {{"a.json", run_of({{"BM_model", 1}, {"BM_raw", 1}})}};
  const auto message = [&](const nlohmann::json& gate) {
    try {
      check_speed_gate(gate, "gate.json", runs);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  nlohmann::json g = gate_of(1);
  g["format"] = 3;
  EXPECT_NE(message(g).find("gate.json: not a speed gate"), std::string::npos);
  EXPECT_NE(message({{"format", "grapebench-speed-gate-1"}, {"ratios", nlohmann::json::array()}}).find("'ratios'"),
            std::string::npos);
  for (const double bad : {0.0, -1.0, 1000.0}) EXPECT_NE(message(gate_of(bad)).find("ratios[0].max"), std::string::npos);
  g = gate_of(1);
  g["ratios"][0]["denominator"] = "BM_gone";
  EXPECT_NE(message(g).find("no run holds benchmark 'BM_gone'"), std::string::npos);
  g = gate_of(1);
  g["ratios"][0]["threshold"] = 2;
  EXPECT_NE(message(g).find("ratios[0].threshold: unknown key"), std::string::npos);
  g = gate_of(1);
  g["ratios"][0]["numerator"] = 5;
  EXPECT_NE(message(g).find("ratios[0].numerator"), std::string::npos);
}

// Google Benchmark wrote "rotation_error_deg": NaN for the cv of a counter that was 0
// in every repetition; nlohmann refuses it.
TEST(BenchmarkJson, BareNanAndInfinityOutsideStringsBecomeNull) {
  const std::string text = R"({"a": NaN, "b": -Infinity, "c": [Infinity, 1], "s": "NaN \"Infinity\" -NaN", "d": 2})";
  const nlohmann::json j = nlohmann::json::parse(benchmark_json_text(text));
  EXPECT_TRUE(j["a"].is_null());
  EXPECT_TRUE(j["b"].is_null());
  EXPECT_TRUE(j["c"][0].is_null());
  EXPECT_EQ(j["s"], "NaN \"Infinity\" -NaN");
  EXPECT_EQ(j["d"], 2);
}

}  // namespace
}  // namespace grapebench
