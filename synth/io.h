// Writing synth outputs: ground-truth JSON and atomic files.
#pragma once

#include "synth/generate.h"
#include "synth/ground_truth.h"
#include "synth/params.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace grapebench {

// Writes `bytes` to a temporary file beside `path`, then renames it into place, so a
// reader never sees a half-written file. Throws InputError naming the path.
void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

// Parses JSON text nested at most `max_depth` deep (a hostile file a million arrays
// deep would overflow the stack further on) and UTF-8 throughout. Throws nlohmann's
// parse_error, or std::runtime_error "nested deeper than N" / "not UTF-8 at byte N".
nlohmann::json parse_json_bounded(std::string_view text, int max_depth = 64);

nlohmann::ordered_json params_json(const BunchParams& p);

struct BunchRecord {
  std::string preset;
  std::uint64_t seed = 0;  // this bunch's own seed
  int index = 0;           // position in the scene
  BunchParams params;
  GenerationReport report;
};

// The ground-truth document (units in key names: _m, _m3, _cm3, _g).
nlohmann::ordered_json ground_truth_json(const Bunch& bunch, const GroundTruth& truth,
                                         const BunchRecord& record);

}  // namespace grapebench
