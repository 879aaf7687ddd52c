// An external program's answer (protocol version 2, every output kind), checked
// against a request of 3 points and 2 classes.
#include "algorithms/external/external_estimator.h"
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
  // What lands in the case file (the notes, or the message of a failed row) must be
  // UTF-8: a type_error escaping here is a finding (exit 3 for the whole run, issue 39).
  try {
    const grapebench::Estimate e = grapebench::parse_external_answer(j, p, 3);
    (void)nlohmann::json(e.notes).dump();
  } catch (const grapebench::InputError& e) {
    (void)nlohmann::json(std::string(e.what())).dump();
  }
  return 0;
}
