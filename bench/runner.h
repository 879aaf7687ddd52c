// `grapebench run`: every case of a scene set (conditions x bunches), in parallel,
// resumable and shardable, then scores, tables and the report.
#pragma once

#include "bench/case_run.h"
#include "bench/scene.h"
#include "bench/scoring.h"

#include <filesystem>
#include <string>
#include <vector>

namespace grapebench {

struct RunOptions {
  std::filesystem::path out;  // the scene's folder: cases/, results.csv, report.html, ...
  int threads = 0;            // 0: all cores; results do not depend on it
  int shard_index = 0, shard_count = 1;  // run the cases with flat index % count == index
  bool resume = true;         // reuse case files whose key matches
  bool progress = true;       // a bar on a terminal, log lines otherwise
  bool quiet = false;         // no progress at all
};

struct RunOutcome {
  int cases = 0;      // in the whole scene set
  int computed = 0;   // run now
  int reused = 0;     // found finished in cases/
  bool complete = false;  // every case present: the tables and report were written
  std::string leaderboard;
};

RunOutcome run_scene_set(const SceneSet& set, const RunOptions& options);

// Joins the case files of shard folders into `options.out` and writes the tables
// and report; throws InputError naming the missing or mismatched cases.
RunOutcome merge_shards(const SceneSet& set, const std::vector<std::filesystem::path>& shard_dirs,
                        const RunOptions& options);

// One line of the scores table (summary.json, leaderboard, report).
struct ScoreRow {
  int condition = 0;
  std::string estimator, type, quantity;
  Score score;
  double peak_heap_mb_max = 0;  // largest peak heap of one run, MB (NaN: not measured); not deterministic
};
std::vector<ScoreRow> score_cases(const SceneSet& set, const std::vector<CaseResult>& cases);

// Registration per condition over its successful cases (summary.json, report).
struct RegistrationRow {
  int cases = 0, failed = 0;
  double rotation_max_deg_mean = 0;   // mean over cases of the per-case worst view
  double rotation_max_deg_worst = 0;
  double translation_max_mm_mean = 0;
  // Means over the cases of the pipeline's label scores (case_run.h).
  double segmentation_precision = 0, segmentation_recall = 0, peduncle_kept = 0, body_kept = 0;
};
std::vector<RegistrationRow> registration_rows(const SceneSet& set, const std::vector<CaseResult>& cases);

}  // namespace grapebench
