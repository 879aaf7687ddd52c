#include "bench/runner.h"

#include "bench/build_info.h"
#include "bench/outputs.h"
#include "bench/progress.h"
#include "synth/io.h"

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

namespace grapebench {

namespace fs = std::filesystem;

namespace {

struct CaseRef {
  int condition = 0;
  BunchJob job;
  std::string key;
  fs::path file;
};

std::vector<CaseRef> all_cases(const SceneSet& set, const fs::path& out) {
  std::vector<CaseRef> refs;
  for (std::size_t c = 0; c < set.conditions.size(); ++c) {
    for (const auto& job : bunch_jobs(set.conditions[c].scene)) {
      char name[48];
      std::snprintf(name, sizeof name, "c%04zu_b%04d.json", c, job.index);
      refs.push_back({static_cast<int>(c), job, case_key(set.conditions[c], job), out / "cases" / name});
    }
  }
  return refs;
}

// A finished case file with the expected key, computed by this build unless
// `any_build`; `other_build` counts the files that match but another build computed.
std::optional<CaseResult> read_case(const CaseRef& ref, const fs::path& file, bool any_build, int* other_build) {
  const std::string& key = ref.key;
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  try {
    const auto j = nlohmann::json::parse(in);
    CaseResult c = case_from_json(j);
    if (c.key != key) return std::nullopt;
    // A file whose indices are not its place's is foreign or edited: its condition
    // would index the scene's conditions unchecked further on.
    if (c.condition != ref.condition || c.bunch != ref.job.index) return std::nullopt;
    if (c.build != build_identity()) {
      if (other_build) ++*other_build;
      if (!any_build) return std::nullopt;
    }
    return c;
  } catch (const std::exception&) {
    return std::nullopt;  // unreadable (foreign or damaged): recompute
  }
}

}  // namespace

RunOutcome run_scene_set(const SceneSet& set, const RunOptions& o) {
  if (o.shard_count < 1 || o.shard_index < 0 || o.shard_index >= o.shard_count) {
    throw InputError("--shard i/N needs 0 <= i < N, got " + std::to_string(o.shard_index) + "/" +
                     std::to_string(o.shard_count));
  }
  for (const auto& c : set.conditions) {
    if (c.scene.estimators.empty()) throw InputError(set.base.path + ": `run` needs an `estimators:` list");
  }
  const int threads = o.threads > 0 ? o.threads : static_cast<int>(tbb::info::default_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  fs::create_directories(o.out / "cases");
  const auto refs = all_cases(set, o.out);
  RunOutcome outcome;
  outcome.cases = static_cast<int>(refs.size());
  std::vector<std::optional<CaseResult>> results(refs.size());
  std::vector<std::size_t> pending;
  for (std::size_t i = 0; i < refs.size(); ++i) {
    if (static_cast<int>(i % static_cast<std::size_t>(o.shard_count)) != o.shard_index) continue;
    if (o.resume) results[i] = read_case(refs[i], refs[i].file, o.reuse_other_builds, &outcome.other_build);
    if (results[i]) {
      ++outcome.reused;
    } else {
      pending.push_back(i);
    }
  }
  Progress progress("case", static_cast<int>(pending.size()), o.verbosity);
  tbb::parallel_for(std::size_t{0}, pending.size(), std::size_t{1}, [&](std::size_t p) {
    const CaseRef& ref = refs[pending[p]];
    CaseResult r = run_case(set.conditions[static_cast<std::size_t>(ref.condition)], ref.condition, ref.job);
    // Written atomically as soon as it is done: an interrupted run resumes from here.
    write_file_atomic(ref.file, case_to_json(r).dump(1) + "\n");
    progress.done("condition " + std::to_string(r.condition) + ", bunch " + std::to_string(r.bunch), !r.ok);
    results[pending[p]] = std::move(r);
  });
  outcome.computed = static_cast<int>(pending.size());
  // Other shards' cases may already be here (a shared folder); the tables need all.
  std::vector<CaseResult> cases;
  for (std::size_t i = 0; i < refs.size(); ++i) {
    if (!results[i]) results[i] = read_case(refs[i], refs[i].file, o.reuse_other_builds, nullptr);
    if (!results[i]) return outcome;
    cases.push_back(*results[i]);
  }
  outcome.leaderboard = write_outputs(set, cases, o.out, o.threads);
  outcome.complete = true;
  return outcome;
}

RunOutcome merge_shards(const SceneSet& set, const std::vector<fs::path>& shard_dirs, const RunOptions& o) {
  fs::create_directories(o.out / "cases");
  const auto refs = all_cases(set, o.out);
  RunOutcome outcome;
  outcome.cases = static_cast<int>(refs.size());
  std::vector<CaseResult> cases;
  std::string missing;
  int n_missing = 0;
  for (const auto& ref : refs) {
    std::optional<CaseResult> found = read_case(ref, ref.file, o.reuse_other_builds, nullptr);
    for (const auto& d : shard_dirs) {
      if (found) break;
      found = read_case(ref, d / "cases" / ref.file.filename(), o.reuse_other_builds, &outcome.other_build);
      if (found) write_file_atomic(ref.file, case_to_json(*found).dump(1) + "\n");
    }
    if (!found) {
      if (++n_missing <= 5) missing += " " + ref.file.filename().string();
      continue;
    }
    ++outcome.reused;
    cases.push_back(*found);
  }
  if (n_missing > 0) {
    throw InputError("merge: " + std::to_string(n_missing) + " of " + std::to_string(refs.size()) +
                     " cases are in none of the shard folders (or were run with other parameters, or by another build:"
                     " --reuse-other-builds takes those):" + missing +
                     (n_missing > 5 ? " ..." : ""));
  }
  outcome.leaderboard = write_outputs(set, cases, o.out, o.threads);
  outcome.complete = true;
  return outcome;
}

}  // namespace grapebench
