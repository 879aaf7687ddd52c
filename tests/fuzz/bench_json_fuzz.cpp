// `grapebench compare-bench`: Google Benchmark JSON, compared with itself.
// Corpus: tests/bench/data/*bench*.json.
#include "bench/bench_compare.h"
#include "synth/config.h"
#include "synth/io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nlohmann::json j;
  try {
    j = grapebench::parse_json_bounded(grapebench::fuzz_text(data, size));
  } catch (const std::exception&) {
    return 0;
  }
  try {
    (void)grapebench::compare_benchmarks(j, j, 0.1);
  } catch (const grapebench::InputError&) {
  }
  return 0;
}
