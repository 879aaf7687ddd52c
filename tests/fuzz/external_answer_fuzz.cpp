// An external program's answer (protocol version 2, every output kind), checked
// against a request of 3 points and 2 classes.
#include "algorithms/external_estimator.h"
#include "synth/io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  grapebench::ExternalParams p;
  p.command = {"fuzz"};
  p.version = 2;
  p.quantities = {grapebench::Quantity::Volume, grapebench::Quantity::Height};
  nlohmann::json j;
  try {
    j = grapebench::parse_json_bounded(grapebench::fuzz_text(data, size));
  } catch (const std::exception&) {  // the harness reports "not JSON"
    return 0;
  }
  try {
    (void)grapebench::parse_external_answer(j, p, 3);
  } catch (const grapebench::InputError&) {
  }
  return 0;
}
