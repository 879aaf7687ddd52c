// `grapebench run`: every case of a scene set (conditions x bunches), in parallel,
// resumable and shardable, then scores, tables and the report.
#pragma once

#include "bench/case_run.h"
#include "bench/progress.h"
#include "bench/scene.h"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace grapebench {

struct RunOptions {
  std::filesystem::path out;  // the scene's folder: cases/, results.csv, report.html, ...
  int threads = 0;            // 0: all cores; results do not depend on it
  int shard_index = 0, shard_count = 1;  // run the cases with flat index % count == index
  bool resume = true;         // reuse case files whose key matches
  bool reuse_other_builds = false;  // also reuse cases another build (build_identity()) computed
  Verbosity verbosity = Verbosity::normal;  // progress: a bar on a terminal, log lines otherwise
  std::filesystem::path cycles_cache;  // Cycles' images kept and reused here; empty: out/cycles_cache
  // Called, from the worker that finished it, after each case computed now: cases done
  // so far, cases to compute, "condition c, bunch b", whether it failed (the Python
  // package's progress line). Must be thread-safe.
  std::function<void(int done, int total, const std::string& detail, bool failed)> on_case;
};

struct RunOutcome {
  int cases = 0;      // in the whole scene set
  int computed = 0;   // run now
  int reused = 0;     // found finished in cases/
  int other_build = 0;  // finished cases of another build: recomputed, or reused with reuse_other_builds
  int tampered = 0;     // case files whose content did not match their digest: recomputed
  bool complete = false;  // every case present: the tables and report were written
  std::string leaderboard;
};

RunOutcome run_scene_set(const SceneSet& set, const RunOptions& options);

// Joins the case files of shard folders into `options.out` and writes the tables
// and report; throws InputError naming the missing or mismatched cases.
RunOutcome merge_shards(const SceneSet& set, const std::vector<std::filesystem::path>& shard_dirs,
                        const RunOptions& options);

}  // namespace grapebench
