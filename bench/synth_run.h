// Generating the bunches of a scene: ground truth, meshes, summaries.
#pragma once

#include "bench/progress.h"
#include "bench/scene.h"
#include "synth/generate.h"
#include "synth/ground_truth.h"
#include "synth/mesh.h"

#include <filesystem>
#include <string>
#include <vector>

namespace grapebench {

struct SynthOptions {
  std::filesystem::path out;  // empty: write nothing
  bool write_mesh = true;
  MeshOptions mesh;
  int threads = 0;  // 0: all cores
  Verbosity verbosity = Verbosity::normal;
  double alpha_wrap = 0;  // m: also the alpha wrap of each bunch with this carving radius; 0: not
};

struct SynthResult {
  BunchJob job;
  GroundTruth truth;
  GenerationReport report;
  double seconds = 0;  // wall time of generation and ground truth, not written to files
};

// Generates every job in parallel; results are in job order whatever the thread
// count, and the files written are byte-identical for the same jobs.
std::vector<SynthResult> run_synth(const std::vector<BunchJob>& jobs, const SynthOptions& options);

// Table of the ground truth (deterministic: no timings).
std::string synth_summary_csv(const std::vector<SynthResult>& results);
std::string synth_summary_table(const std::vector<SynthResult>& results);

}  // namespace grapebench
