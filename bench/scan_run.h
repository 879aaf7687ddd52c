// Scanning the bunches of a scene with its sensor and rig.
#pragma once

#include "bench/progress.h"
#include "bench/scene.h"
#include "sensors/scan.h"

#include <filesystem>
#include <string>

namespace grapebench {

struct ScanRunOptions {
  std::filesystem::path out;  // one folder per bunch: bunch_NNNN/
  int threads = 0;            // 0: all cores
  int only_bunch = -1;        // scan one bunch of the scene
  bool merged = false;        // also write every view's points in the world frame
  std::filesystem::path cycles_cache;  // Cycles' images kept and reused here (a run's cycles_cache/); empty: none
  Verbosity verbosity = Verbosity::normal;
};

struct ScanSummary {
  int bunch = 0;
  int views = 0;
  std::size_t valid_points = 0;
  std::uint64_t rays = 0;
  double seconds = 0;  // capture time (all views)
};

// Generates each bunch (ground truth and mesh beside its scan) and scans it.
std::vector<ScanSummary> run_scans(const Scene& scene, const ScanRunOptions& options);
std::string scan_summary_table(const std::vector<ScanSummary>& rows);

}  // namespace grapebench
