// The scene reader and sweep expansion (`grapebench run/scan` on a scene file).
// Corpus: scenes/ and tests/bench/data/.
#include "bench/scene_file.h"
#include "synth/config.h"

#include <nlohmann/json.hpp>
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 64 * 1024) return 0;  // scenes are small; long inputs only slow the search
  try {
    const std::string text = grapebench::fuzz_text(data, size);
    const grapebench::SceneSet set = grapebench::parse_scene_set(text, "fuzz.yaml");
    // The manifest echoes an accepted scene's text in JSON: it must be UTF-8 (a
    // type_error escaping here is a finding: exit 3 after a whole run, issue 39).
    (void)nlohmann::json(text).dump();
    (void)set;
  } catch (const grapebench::InputError&) {
  }
  return 0;
}
