// `grapebench compare-bench` and `speed-gate`: Google Benchmark JSON (bare NaN and
// Infinity allowed, as Google Benchmark writes them), compared with itself and checked
// as both a run and a speed gate. Corpus: tests/fuzz/corpus/bench_json.
#include "bench/bench_compare.h"
#include "synth/config.h"
#include "synth/io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nlohmann::json j;
  try {
    j = grapebench::parse_json_bounded(grapebench::benchmark_json_text(grapebench::fuzz_text(data, size)));
  } catch (const std::exception&) {
    return 0;
  }
  try {
    (void)grapebench::compare_benchmarks(j, j, 0.1);
  } catch (const grapebench::InputError&) {
  }
  try {
    (void)grapebench::check_speed_gate(j, "gate.json", {{"run.json", j}});
  } catch (const grapebench::InputError&) {
  }
  return 0;
}
