// The scene reader and sweep expansion (`grapebench run/scan` on a scene file).
// Corpus: scenes/ and tests/bench/data/.
#include "bench/scene_file.h"
#include "synth/config.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 64 * 1024) return 0;  // scenes are small; long inputs only slow the search
  try {
    const grapebench::SceneSet set = grapebench::parse_scene_set(grapebench::fuzz_text(data, size), "fuzz.yaml");
    (void)set;
  } catch (const grapebench::InputError&) {
  }
  return 0;
}
