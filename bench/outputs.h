// The files a finished run writes into its folder: results.csv, timings.csv,
// summary.json, timings.json, manifest.json, size_error.csv/.md (seed 003), the report
// and its plots. Each is written atomically.
#pragma once

#include "bench/case_result.h"
#include "bench/scene.h"

#include <filesystem>
#include <string>
#include <vector>

namespace grapebench {

// Writes every output of a complete set of cases into `out`; returns the leaderboard
// text. `threads` is recorded in the manifest.
std::string write_outputs(const SceneSet& set, const std::vector<CaseResult>& cases, const std::filesystem::path& out,
                          int threads);

// What manifest.json holds: the scene (its file's text and every condition read back),
// the bunch seeds, the build, the machine, `threads`, and which builds computed `cases`.
nlohmann::ordered_json manifest_json(const SceneSet& set, const std::vector<CaseResult>& cases, int threads);

}  // namespace grapebench
