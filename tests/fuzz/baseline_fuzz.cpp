// `grapebench check`: a baseline against itself (both sides of the comparison are
// read with the same checks). Corpus: results/baseline/.
#include "bench/check.h"
#include "synth/config.h"
#include "synth/io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nlohmann::json j;
  try {
    j = grapebench::parse_json_bounded(grapebench::fuzz_text(data, size));
  } catch (const std::exception&) {  // main() reports unparsable files as InputError
    return 0;
  }
  try {
    (void)grapebench::check_against_baseline(j, j, "run", "baseline");
  } catch (const grapebench::InputError&) {
  }
  return 0;
}
