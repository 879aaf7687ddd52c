// The case-file reader of resume and merge: bounded JSON, digest, fields and ranges.
// Every failure must be an exception the runner turns into "recompute".
// Corpus: case files of a run (scripts/fuzz.sh makes them).
#include "bench/case_result.h"
#include "synth/io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const nlohmann::json j = grapebench::parse_json_bounded(grapebench::fuzz_text(data, size));
    const grapebench::CaseResult c = grapebench::case_from_json(j);
    (void)grapebench::case_to_json(c);
  } catch (const std::exception&) {  // the runner recomputes such a case
  }
  return 0;
}
