#include "bench/runner.h"

#include "bench/build_info.h"
#include "bench/outputs.h"
#include "bench/progress.h"
#include "bench/scene_file.h"
#include "sensors/render/cycles_render.h"
#include "synth/confined_program.h"
#include "synth/fnv1a.h"
#include "synth/io.h"
#include "synth/read_regular_file.h"

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
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

// Pending cases computed together: one bunch under conditions whose scenes differ only
// in sensors sharing a together_key (seed 001's sweep over the `ray` renderer's light:
// each pair rendered once for the three lights, sensors/render/ray_render.h), with a
// protocol that runs cases together; every other case alone. Ordered by their first.
std::vector<std::vector<std::size_t>> together_groups(const SceneSet& set, const std::vector<CaseRef>& refs,
                                                      const std::vector<std::size_t>& pending) {
  std::vector<std::string> key(set.conditions.size());
  for (std::size_t c = 0; c < set.conditions.size(); ++c) {
    const Scene& s = set.conditions[c].scene;
    if (!s.sensor || !protocol_runs_together(s.protocol)) continue;
    const std::string t = s.sensor->together_key();
    if (t.empty()) continue;
    nlohmann::ordered_json j = scene_json(s);
    j["sensor"] = t;
    key[c] = j.dump();
  }
  std::map<std::pair<std::string, int>, std::size_t> at;  // (key, bunch) -> its group
  std::vector<std::vector<std::size_t>> groups;
  for (const std::size_t i : pending) {
    const std::string& k = key[static_cast<std::size_t>(refs[i].condition)];
    if (k.empty()) {
      groups.push_back({i});
      continue;
    }
    const auto [it, fresh] = at.try_emplace({k, refs[i].job.index}, groups.size());
    if (fresh) groups.push_back({i});
    else groups[it->second].push_back(i);
  }
  return groups;
}

// What was found at a case's place.
struct CaseRead {
  std::optional<CaseResult> result;  // usable
  bool other_build = false;          // finished by another build (used only with any_build)
  bool tampered = false;             // its content does not match its digest
};

// Case files hold one bunch's rows and diagnostics: a few MB at most.
constexpr std::size_t kMaxCaseFileBytes = std::size_t{256} << 20;

// A finished case file with the expected key, computed by this build unless
// `any_build`, whose content matches its digest and whose fields are the scene's.
CaseRead read_case(const SceneSet& set, const CaseRef& ref, const fs::path& file, bool any_build) {
  CaseRead out;
  try {
    // Not a regular file (a FIFO, a link to a device) or too large: recomputed.
    const auto j = parse_json_bounded(read_regular_file(file, kMaxCaseFileBytes));
    CaseResult c = case_from_json(j);
    if (c.key != ref.key) return out;
    // A file whose indices are not its place's is foreign or edited: its condition
    // would index the scene's conditions unchecked further on.
    if (c.condition != ref.condition || c.bunch != ref.job.index) return out;
    const auto& estimators = set.conditions[static_cast<std::size_t>(ref.condition)].scene.estimators;
    for (const EstimateRow& row : c.rows) {
      if (std::none_of(estimators.begin(), estimators.end(), [&](const EstimatorSpec& e) { return e.name == row.estimator; }))
        return out;
    }
    if (c.build != build_identity()) {
      out.other_build = true;
      if (!any_build) return out;
    }
    out.result = std::move(c);
  } catch (const CaseDigestMismatch&) {
    out.tampered = true;
  } catch (const std::exception&) {
    // unreadable (foreign, damaged or out of range): recompute
  }
  return out;
}

// An exclusive claim on one case across processes (flock on cases/<case>.lock): two
// runs on one --out never compute the same case at once. Released when destroyed, or
// by the kernel when the process dies.
class CaseClaim {
 public:
  CaseClaim(const fs::path& case_file, bool wait) {
    const std::string lock = fs::path(case_file).replace_extension(".lock").string();
    fd_ = open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw InputError(lock + ": cannot create the case's lock file: " + std::strerror(errno));
    int rc;
    while ((rc = flock(fd_, wait ? LOCK_EX : LOCK_EX | LOCK_NB)) != 0 && errno == EINTR) {
    }
    held_ = rc == 0;
  }
  ~CaseClaim() { close(fd_); }
  CaseClaim(const CaseClaim&) = delete;
  CaseClaim& operator=(const CaseClaim&) = delete;
  bool held() const { return held_; }

 private:
  int fd_ = -1;
  bool held_ = false;
};

// The count of a finished shard's shard.json in `dir`, or 0.
int shard_count_in(const fs::path& dir) {
  try {
    const auto j = parse_json_bounded(read_regular_file(dir / "shard.json", std::size_t{1} << 20));
    if (j.value("format", "") != "grapebench-shard-1") return 0;
    return std::max(0, j.at("count").get<int>());
  } catch (const std::exception&) {
    return 0;  // damaged or foreign: as if absent
  }
}

// For merge's error: the shards (i/N) the missing cases belong to, N as the finished
// shards' shard.json say, and the --from folders holding no finished shard, so a
// cancelled or failed task is named and can be run again alone.
std::string missing_shards(std::size_t n_cases, const std::vector<std::size_t>& missing,
                           const std::vector<fs::path>& dirs) {
  std::set<int> counts;
  std::string unfinished;
  for (const auto& d : dirs) {
    if (const int n = shard_count_in(d); n > 0) {
      counts.insert(n);
      continue;
    }
    std::error_code ec;
    int files = 0;
    for (const auto& e : fs::directory_iterator(d / "cases", ec)) files += e.path().extension() == ".json";
    unfinished += (unfinished.empty() ? "" : ", ") + d.string() +
                  (!fs::exists(d) ? " (absent)"
                   : files == 0   ? " (no cases)"
                                  : " (" + std::to_string(files) + " case files, unfinished)");
  }
  std::string m;
  if (counts.size() == 1) {
    const int n = *counts.begin();
    std::set<int> shards;
    for (const std::size_t k : missing) shards.insert(static_cast<int>(k % static_cast<std::size_t>(n)));
    m = "\n  missing shards:";
    for (const int i : shards) m += " " + std::to_string(i) + "/" + std::to_string(n);
  } else {
    // No shard count to go by (no shard finished, or shards of different counts):
    // the cases' indices; shard i/N ran those with index mod N = i.
    m = counts.empty() ? "\n  no --from folder holds a finished shard (shard.json); missing case indices (of 0-"
                       : "\n  the --from folders hold shards of different counts; missing case indices (of 0-";
    m += std::to_string(n_cases - 1) + "):";
    for (std::size_t k = 0; k < missing.size() && k < 20; ++k) m += " " + std::to_string(missing[k]);
    if (missing.size() > 20) m += " ...";
  }
  if (!unfinished.empty()) m += "\n  --from folders without a finished shard: " + unfinished;
  return m;
}

}  // namespace

namespace {

// One --out folder holds one scene (issue 39: two scene files with the same `name` on
// one --out both ran, and one's results replaced the other's silently). The folder
// records the scene file it holds; another file of other text is refused. The same
// file edited, or a copy of it, runs on.
void claim_scene_folder(const SceneSet& set, const fs::path& out) {
  std::string text;
  try {
    text = read_scene_text(set.base.path);
  } catch (const InputError&) {
    return;  // a scene given as text (no file to name)
  }
  std::error_code ec;
  const std::string source = fs::weakly_canonical(set.base.path, ec).string();
  char digest[17];
  std::snprintf(digest, sizeof digest, "%016llx", static_cast<unsigned long long>(fnv1a(text)));
  const fs::path marker = out / "scene_source.json";
  nlohmann::json was;
  try {
    was = parse_json_bounded(read_regular_file(marker, std::size_t{1} << 16));
  } catch (const std::exception&) {
    was = nullptr;  // absent or unreadable: claimed below
  }
  const auto text_of = [&](const char* key) {
    return was.is_object() && was.contains(key) && was[key].is_string() ? was[key].get<std::string>() : std::string();
  };
  if (!text_of("path").empty() && text_of("path") != source && text_of("digest") != digest) {
    throw InputError(out.string() + " holds the run of " + text_of("path") + ", another scene named '" +
                     set.base.name + "' than " + source + ": give one of them another `name`, or another --out");
  }
  write_file_atomic(marker, nlohmann::json{{"format", "grapebench-scene-source-1"}, {"path", source}, {"digest", digest}}
                                .dump(1) + "\n");
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
  claim_scene_folder(set, o.out);
  hide_from_programs(o.out);  // no program it starts sees the cases and their truth
  // Cycles' images kept in the run folder (or the one given): a resumed run, or one
  // with another estimator, renders none twice (sensors/render/cycles_render.h). Their
  // object-index images are per-berry truth: hidden from programs like the run folder.
  std::optional<CyclesCacheScope> cache;
  std::vector<char> on_cycles;  // per condition, its sensor renders on Cycles
  for (const Condition& c : set.conditions)
    on_cycles.push_back(c.scene.sensor && c.scene.sensor->describe().value("renderer", std::string()) == "cycles");
  const bool cycles = std::find(on_cycles.begin(), on_cycles.end(), 1) != on_cycles.end();
  if (cycles) {
    const fs::path folder = o.cycles_cache.empty() ? o.out / "cycles_cache" : o.cycles_cache;
    fs::create_directories(folder);
    hide_from_programs(folder);
    cache.emplace(folder);
  }
  const auto refs = all_cases(set, o.out);
  RunOutcome outcome;
  outcome.cases = static_cast<int>(refs.size());
  std::vector<std::optional<CaseResult>> results(refs.size());
  const auto look = [&](std::size_t i, bool count) {
    CaseRead read = read_case(set, refs[i], refs[i].file, o.reuse_other_builds);
    if (count && read.other_build) ++outcome.other_build;
    if (count && read.tampered) ++outcome.tampered;
    results[i] = std::move(read.result);
  };
  std::vector<std::size_t> pending;
  for (std::size_t i = 0; i < refs.size(); ++i) {
    if (static_cast<int>(i % static_cast<std::size_t>(o.shard_count)) != o.shard_index) continue;
    if (o.resume) look(i, true);
    if (results[i]) {
      ++outcome.reused;
    } else {
      pending.push_back(i);
    }
  }
  // A case to render on Cycles: Blender must be there (exit 2 naming the package, before
  // any case; each case would otherwise fail alone with the same reason).
  const bool renders_on_cycles = std::any_of(pending.begin(), pending.end(), [&](std::size_t i) {
    return on_cycles[static_cast<std::size_t>(refs[i].condition)] != 0;
  });
  if (renders_on_cycles) find_blender();
  Progress progress("case", static_cast<int>(pending.size()), o.verbosity);
  std::atomic<int> computed{0};
  std::mutex busy_mutex;
  std::vector<std::size_t> busy;  // claimed by another run on this folder: waited for after ours
  const auto finish = [&](std::size_t i, CaseResult r) {
    const CaseRef& ref = refs[i];
    // Written atomically as soon as it is done: an interrupted run resumes from here.
    write_file_atomic(ref.file, case_to_json(r).dump(1) + "\n");
    const std::string detail = "condition " + std::to_string(r.condition) + ", bunch " + std::to_string(r.bunch);
    progress.done(detail, !r.ok);
    const bool failed = !r.ok;
    results[i] = std::move(r);
    const int done = ++computed;
    if (o.on_case) o.on_case(done, static_cast<int>(pending.size()), detail, failed);
  };
  const auto compute = [&](std::size_t i) {
    const CaseRef& ref = refs[i];
    finish(i, run_case(set.conditions[static_cast<std::size_t>(ref.condition)], ref.condition, ref.job));
  };
  const auto compute_together = [&](const std::vector<std::size_t>& group) {
    std::vector<const Condition*> conditions;
    std::vector<int> indices;
    for (const std::size_t i : group) {
      conditions.push_back(&set.conditions[static_cast<std::size_t>(refs[i].condition)]);
      indices.push_back(refs[i].condition);
    }
    std::vector<CaseResult> r = run_cases_together(conditions, indices, refs[group.front()].job);
    for (std::size_t k = 0; k < group.size(); ++k) finish(group[k], std::move(r[k]));
  };
  // Claimed, a case is looked for again: another run may have finished it since
  // (`waited`: we waited for the run that held it; even --no-resume takes its result).
  const auto to_compute = [&](std::size_t i, bool waited) {
    if (o.resume || waited) look(i, false);
    if (!results[i]) return true;
    progress.done("condition " + std::to_string(refs[i].condition) + ", bunch " + std::to_string(refs[i].job.index) +
                      " (finished by another run)",
                  false);
    return false;
  };
  const auto claimed = [&](std::size_t i, bool waited) {
    if (to_compute(i, waited)) compute(i);
  };
  const auto groups = together_groups(set, refs, pending);
  tbb::parallel_for(std::size_t{0}, groups.size(), std::size_t{1}, [&](std::size_t g) {
    std::vector<std::unique_ptr<CaseClaim>> claims;  // held until the group is computed
    std::vector<std::size_t> mine;
    for (const std::size_t i : groups[g]) {
      auto claim = std::make_unique<CaseClaim>(refs[i].file, false);
      if (!claim->held()) {
        const std::lock_guard<std::mutex> lock(busy_mutex);
        busy.push_back(i);
      } else if (to_compute(i, false)) {
        mine.push_back(i);
        claims.push_back(std::move(claim));
      }
    }
    if (mine.size() == 1) compute(mine.front());
    else if (!mine.empty()) compute_together(mine);
  });
  std::sort(busy.begin(), busy.end());
  tbb::parallel_for(std::size_t{0}, busy.size(), std::size_t{1}, [&](std::size_t b) {
    const CaseClaim claim(refs[busy[b]].file, true);  // until the other run is done with it
    claimed(busy[b], true);
  });
  outcome.computed = computed;
  outcome.reused += static_cast<int>(pending.size()) - computed;
  // This shard is finished: `merge` reads the shard count here to name the shards
  // whose cases are missing (a cancelled or failed task leaves no shard.json).
  if (o.shard_count > 1) {
    const nlohmann::ordered_json marker = {{"format", "grapebench-shard-1"}, {"scene", set.base.name},
                                           {"index", o.shard_index}, {"count", o.shard_count},
                                           {"cases", outcome.computed + outcome.reused}};
    write_file_atomic(o.out / "shard.json", marker.dump(1) + "\n");
  }
  // Other shards' cases may already be here (a shared folder); the tables need all.
  std::vector<CaseResult> cases;
  for (std::size_t i = 0; i < refs.size(); ++i) {
    if (!results[i]) look(i, false);
    if (!results[i]) return outcome;
    cases.push_back(*results[i]);
  }
  // One writer of the tables at a time (runs sharing the folder write the same bytes).
  const CaseClaim tables(o.out / "cases" / "tables", true);
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
  std::vector<std::size_t> missing_indices;
  for (std::size_t k = 0; k < refs.size(); ++k) {
    const CaseRef& ref = refs[k];
    std::optional<CaseResult> found = read_case(set, ref, ref.file, o.reuse_other_builds).result;
    for (const auto& d : shard_dirs) {
      if (found) break;
      const CaseRead read = read_case(set, ref, d / "cases" / ref.file.filename(), o.reuse_other_builds);
      if (read.other_build) ++outcome.other_build;
      if (read.tampered) ++outcome.tampered;
      found = read.result;
      if (found) write_file_atomic(ref.file, case_to_json(*found).dump(1) + "\n");
    }
    if (!found) {
      missing_indices.push_back(k);
      if (missing_indices.size() <= 5) missing += " " + ref.file.filename().string();
      continue;
    }
    ++outcome.reused;
    cases.push_back(*found);
  }
  if (const std::size_t n_missing = missing_indices.size(); n_missing > 0) {
    throw InputError("merge: " + std::to_string(n_missing) + " of " + std::to_string(refs.size()) +
                     " cases are in none of the shard folders (or were run with other parameters, or by another build:"
                     " --reuse-other-builds takes those):" + missing +
                     (n_missing > 5 ? " ..." : "") + missing_shards(refs.size(), missing_indices, shard_dirs));
  }
  outcome.leaderboard = write_outputs(set, cases, o.out, o.threads);
  outcome.complete = true;
  return outcome;
}

}  // namespace grapebench
