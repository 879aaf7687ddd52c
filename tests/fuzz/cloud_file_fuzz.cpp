// `grapebench estimate`'s PLY and PCD reader: input that starts with "ply" is read as PLY, the rest as PCD.
// Corpus: PLY and PCD files written by `grapebench scan` (scripts/fuzz.sh).
#include "bench/cloud_file.h"
#include "synth/config.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 4 * 1024 * 1024) return 0;
  const std::string bytes = grapebench::fuzz_text(data, size);
  try {
    (void)grapebench::parse_cloud(bytes, "fuzz", bytes.rfind("ply", 0) == 0 ? "ply" : "pcd");
  } catch (const grapebench::InputError&) {
  }
  return 0;
}
