#include "bench/runner.h"

#include "bench/report.h"
#include "bench/size_error.h"
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

// A finished case file with the expected key, or nothing.
std::optional<CaseResult> read_case(const fs::path& file, const std::string& key) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  try {
    const auto j = nlohmann::json::parse(in);
    CaseResult c = case_from_json(j);
    if (c.key != key) return std::nullopt;
    return c;
  } catch (const std::exception&) {
    return std::nullopt;  // unreadable (foreign or damaged): recompute
  }
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string num(double v) {
  if (!std::isfinite(v)) return "NaN";
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

std::string results_csv(const SceneSet& set, const std::vector<CaseResult>& cases) {
  std::ostringstream s;
  s << "scene,condition";
  for (const auto& a : set.base.sweep) s << "," << csv_field(a.key);
  s << ",bunch,preset,seed,estimator,type,quantity,unit,estimate,truth,error,rel_error_pct,ok,watertight,points,"
       "rotation_error_max_deg,translation_error_max_mm,message,frame,roi,region,region_points,region_precision\n";
  for (const auto& c : cases) {
    const Condition& cond = set.conditions[static_cast<std::size_t>(c.condition)];
    for (const auto& r : c.rows) {
      const double k = display_scale(r.quantity);
      s << csv_field(set.base.name) << "," << csv_field(cond.label);
      for (std::size_t a = 0; a < cond.values.size(); ++a) {
        const auto& names = set.base.sweep[a].names;
        s << "," << (names.empty() ? num(cond.values[a]) : csv_field(names[static_cast<std::size_t>(cond.values[a])]));
      }
      s << "," << c.bunch << "," << c.preset << "," << c.seed << "," << csv_field(r.estimator) << "," << r.type << ","
        << r.quantity << "," << display_unit(r.quantity) << ",";
      if (r.ok) {
        s << num(r.estimate * k) << "," << num(r.truth * k) << "," << num((r.estimate - r.truth) * k) << ","
          << num(100 * (r.estimate / r.truth - 1));
      } else {
        s << "NaN," << (c.ok ? num(r.truth * k) : "NaN") << ",NaN,NaN";
      }
      s << "," << (r.ok ? 1 : 0) << "," << (r.watertight ? 1 : 0) << "," << c.points << ","
        << num(c.rotation_error_max_deg) << "," << num(c.translation_error_max_mm) << "," << csv_field(r.error) << ","
        << r.frame << "," << r.roi << "," << r.region << "," << r.region_points << ","
        << (r.region_precision >= 0 ? num(r.region_precision) : "NaN") << "\n";
    }
  }
  return s.str();
}

std::string timings_csv(const SceneSet& set, const std::vector<CaseResult>& cases) {
  std::ostringstream s;
  s << "scene,condition,bunch,estimator,seconds,peak_heap_mb,scan_seconds,segmentation_seconds,registration_seconds,filter_seconds\n";
  for (const auto& c : cases) {
    const Condition& cond = set.conditions[static_cast<std::size_t>(c.condition)];
    std::string last;
    for (const auto& r : c.rows) {
      if (r.estimator == last) continue;  // one timing per estimator run
      last = r.estimator;
      s << csv_field(set.base.name) << "," << csv_field(cond.label) << "," << c.bunch << "," << csv_field(r.estimator)
        << "," << num(r.seconds) << "," << (r.peak_heap_mb >= 0 ? num(r.peak_heap_mb) : "NaN") << ","
        << num(c.scan_seconds) << "," << num(c.segmentation_seconds) << "," << num(c.registration_seconds) << ","
        << num(c.filter_seconds) << "\n";
    }
  }
  return s.str();
}

nlohmann::ordered_json jnum(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); }

nlohmann::ordered_json summary_json(const SceneSet& set, const std::vector<CaseResult>& cases,
                                    const std::vector<ScoreRow>& scores) {
  nlohmann::ordered_json j;
  j["scene"] = set.base.name;
  j["cases"] = cases.size();
  int failed = 0;
  for (const auto& c : cases) failed += c.ok ? 0 : 1;
  j["failed_scans"] = failed;
  nlohmann::ordered_json conds = nlohmann::ordered_json::array();
  for (const auto& c : set.conditions) conds.push_back(c.label);
  j["conditions"] = conds;
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const auto& r : scores) {
    const Score& s = r.score;
    rows.push_back({{"condition", set.conditions[static_cast<std::size_t>(r.condition)].label},
                    {"estimator", r.estimator},
                    {"type", r.type},
                    {"quantity", r.quantity},
                    {"unit", display_unit(r.quantity)},
                    {"cases", s.cases},
                    {"succeeded", s.succeeded},
                    {"success_rate", jnum(s.success_rate)},
                    {"r2", jnum(s.r2)},
                    {"r2_identity", jnum(s.r2_identity)},
                    {"rmse", jnum(s.rmse)},
                    {"mae", jnum(s.mae)},
                    {"bias", jnum(s.bias)},
                    {"mape_pct", jnum(s.mape)},
                    {"slope", jnum(s.slope)},
                    {"intercept", jnum(s.intercept)}});
  }
  j["scores"] = rows;
  nlohmann::ordered_json reg = nlohmann::ordered_json::array();
  const auto regs = registration_rows(set, cases);
  for (std::size_t c = 0; c < set.conditions.size(); ++c) {
    reg.push_back({{"condition", set.conditions[c].label},
                   {"registration", set.conditions[c].scene.pipeline.registration},
                   {"rotation_error_max_deg_mean", regs[c].rotation_max_deg_mean},
                   {"rotation_error_max_deg_worst", regs[c].rotation_max_deg_worst},
                   {"translation_error_max_mm_mean", regs[c].translation_max_mm_mean},
                   {"segmentation", set.conditions[c].scene.pipeline.segmentation},
                   {"segmentation_precision_mean", regs[c].segmentation_precision},
                   {"segmentation_recall_mean", regs[c].segmentation_recall},
                   {"peduncle_kept_mean", regs[c].peduncle_kept},
                   {"body_kept_mean", regs[c].body_kept}});
  }
  j["registration"] = reg;
  return j;
}

nlohmann::ordered_json timings_json(const SceneSet& set, const std::vector<ScoreRow>& scores) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  std::string last;
  for (const auto& r : scores) {
    const std::string id = std::to_string(r.condition) + "/" + r.estimator;
    if (id == last) continue;
    last = id;
    rows.push_back({{"condition", set.conditions[static_cast<std::size_t>(r.condition)].label},
                    {"estimator", r.estimator},
                    {"median_s", jnum(r.score.time_median)},
                    {"p25_s", jnum(r.score.time_p25)},
                    {"p75_s", jnum(r.score.time_p75)},
                    {"peak_heap_mb_max", jnum(r.peak_heap_mb_max)}});
  }
  return rows;
}

std::string git_commit() {
  FILE* p = popen("git rev-parse --short HEAD 2>/dev/null", "r");
  if (!p) return "unknown";
  char buf[64] = {};
  const bool got = std::fgets(buf, sizeof buf, p) != nullptr;
  pclose(p);
  std::string s = got ? buf : "unknown";
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  return s.empty() ? "unknown" : s;
}

nlohmann::ordered_json manifest_json(const SceneSet& set, const RunOptions& o) {
  nlohmann::ordered_json j;
  j["scene_file"] = set.base.path;
  std::ifstream in(set.base.path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  j["scene_text"] = text.str();
  nlohmann::ordered_json sweep = nlohmann::ordered_json::array();
  for (const auto& a : set.base.sweep) sweep.push_back({{"key", a.key}, {"values", a.values}});
  j["sweep"] = sweep;
  nlohmann::ordered_json conds = nlohmann::ordered_json::array();
  for (const auto& c : set.conditions) {
    nlohmann::ordered_json cj = {{"condition", c.label}, {"scene", scene_json(c.scene)}};
    nlohmann::ordered_json seeds = nlohmann::ordered_json::array();
    for (const auto& job : bunch_jobs(c.scene)) seeds.push_back({{"bunch", job.index}, {"preset", job.preset}, {"seed", job.seed}});
    cj["bunch_seeds"] = seeds;
    conds.push_back(cj);
  }
  j["conditions"] = conds;
  j["git_commit"] = git_commit();
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  j["machine"] = {{"host", host}, {"cores", tbb::info::default_concurrency()}};
  j["threads"] = o.threads;
  return j;
}

std::string leaderboard(const SceneSet& set, const std::vector<ScoreRow>& scores) {
  std::ostringstream s;
  char line[256];
  for (std::size_t c = 0; c < set.conditions.size(); ++c) {
    if (!set.conditions[c].label.empty()) s << "-- " << set.conditions[c].label << "\n";
    std::snprintf(line, sizeof line, "  %-18s %-8s %5s %8s %10s %10s %9s %8s %10s %8s\n", "estimator", "quantity",
                  "ok", "R2", "RMSE", "bias", "MAPE %", "slope", "time ms", "heap MB");
    s << line;
    // Volume first, best MAPE first: the leaderboard.
    std::vector<const ScoreRow*> rows;
    for (const auto& r : scores) {
      if (r.condition == static_cast<int>(c)) rows.push_back(&r);
    }
    std::stable_sort(rows.begin(), rows.end(), [](const ScoreRow* a, const ScoreRow* b) {
      if (a->quantity != b->quantity) return a->quantity == "volume" || (b->quantity != "volume" && a->quantity < b->quantity);
      const double ma = std::isfinite(a->score.mape) ? a->score.mape : 1e300;
      const double mb = std::isfinite(b->score.mape) ? b->score.mape : 1e300;
      return ma < mb;
    });
    for (const ScoreRow* r : rows) {
      const Score& x = r->score;
      char ok[16];
      std::snprintf(ok, sizeof ok, "%d/%d", x.succeeded, x.cases);
      std::snprintf(line, sizeof line, "  %-18s %-8s %5s %8.3f %10.2f %10.2f %9.1f %8.3f %10.2f %8.1f  %s\n",
                    r->estimator.c_str(), r->quantity.c_str(), ok, x.r2, x.rmse, x.bias, x.mape, x.slope,
                    x.time_median * 1e3, r->peak_heap_mb_max, display_unit(r->quantity));
      s << line;
    }
  }
  return s.str();
}

void write_outputs(const SceneSet& set, const std::vector<CaseResult>& cases, const RunOptions& o,
                   RunOutcome& outcome) {
  const auto scores = score_cases(set, cases);
  write_file_atomic(o.out / "results.csv", results_csv(set, cases));
  write_file_atomic(o.out / "timings.csv", timings_csv(set, cases));
  write_file_atomic(o.out / "summary.json", summary_json(set, cases, scores).dump(1) + "\n");
  write_file_atomic(o.out / "timings.json", timings_json(set, scores).dump(1) + "\n");
  write_file_atomic(o.out / "manifest.json", manifest_json(set, o).dump(1) + "\n");
  const auto size_cells = size_error_cells(set, cases);
  if (!size_cells.empty()) {
    write_file_atomic(o.out / "size_error.csv", size_error_csv(set, size_cells));
    write_file_atomic(o.out / "size_error_table.md", size_error_table(size_cells));
  }
  const Report report = make_report(set, cases, scores, size_cells);
  fs::create_directories(o.out / "plots");
  for (const auto& [name, svg] : report.svgs) write_file_atomic(o.out / "plots" / name, svg);
  write_file_atomic(o.out / "report.html", report.html);
  outcome.complete = true;
  outcome.leaderboard = leaderboard(set, scores);
}

class Progress {
 public:
  Progress(int total, bool enabled) : total_(total), enabled_(enabled), tty_(isatty(fileno(stderr)) != 0) {
    t0_ = std::chrono::steady_clock::now();
  }
  void done(const CaseResult& c) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++count_;
    if (!enabled_) return;
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    const double eta = count_ > 0 ? el / count_ * (total_ - count_) : 0;
    if (tty_) {
      const int width = 30, fill = total_ > 0 ? width * count_ / total_ : width;
      std::fprintf(stderr, "\r  [%s%s] %d/%d  %.0f s elapsed, ETA %.0f s ", std::string(static_cast<std::size_t>(fill), '#').c_str(),
                   std::string(static_cast<std::size_t>(width - fill), '.').c_str(), count_, total_, el, eta);
      if (count_ == total_) std::fprintf(stderr, "\n");
    } else {
      std::fprintf(stderr, "  case %d/%d (condition %d, bunch %d)%s  %.1f s elapsed, ETA %.0f s\n", count_, total_,
                   c.condition, c.bunch, c.ok ? "" : " FAILED", el, eta);
    }
    std::fflush(stderr);
  }

 private:
  int total_, count_ = 0;
  bool enabled_, tty_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace

std::vector<ScoreRow> score_cases(const SceneSet& set, const std::vector<CaseResult>& cases) {
  std::vector<ScoreRow> out;
  for (std::size_t c = 0; c < set.conditions.size(); ++c) {
    // The scene's estimators, then the rig's floor when the pipeline measures it.
    struct Scored {
      std::string name, type;
      std::vector<Quantity> quantities;
    };
    const Scene& scene = set.conditions[c].scene;
    std::vector<Scored> scored;
    for (const auto& e : scene.estimators) scored.push_back({e.name, e.type, e.quantities});
    if (scene.pipeline.visibility_hull > 0 && scene.pipeline.registration != "single_frame") {
      scored.push_back({"visibility_hull", "visibility_hull", {Quantity::Volume}});
    }
    for (const auto& spec : scored) {
      // Single-frame pipelines score each ROI kind apart ("G_E@manual_r").
      std::vector<std::string> rois;
      for (const auto& cr : cases) {
        if (cr.condition != static_cast<int>(c)) continue;
        for (const auto& r : cr.rows) {
          if (r.estimator == spec.name && std::find(rois.begin(), rois.end(), r.roi) == rois.end()) rois.push_back(r.roi);
        }
      }
      if (rois.empty()) rois.push_back("");
      for (const auto& roi : rois) {
        for (const Quantity q : spec.quantities) {
          const std::string qn = quantity_name(q);
          const double k = display_scale(qn);
          std::vector<double> est, truth, secs;
          double heap = std::nan("");
          int n = 0;
          for (const auto& cr : cases) {
            if (cr.condition != static_cast<int>(c)) continue;
            for (const auto& r : cr.rows) {
              if (r.estimator != spec.name || r.quantity != qn || r.roi != roi) continue;
              ++n;
              if (cr.ok) secs.push_back(r.seconds);
              if (r.peak_heap_mb >= 0) heap = std::isnan(heap) ? r.peak_heap_mb : std::max(heap, r.peak_heap_mb);
              if (r.ok) {
                est.push_back(r.estimate * k);
                truth.push_back(r.truth * k);
              }
            }
          }
          out.push_back({static_cast<int>(c), roi.empty() ? spec.name : spec.name + "@" + roi, spec.type, qn,
                         score(est, truth, n, secs), heap});
        }
      }
    }
  }
  return out;
}

std::vector<RegistrationRow> registration_rows(const SceneSet& set, const std::vector<CaseResult>& cases) {
  std::vector<RegistrationRow> rows(set.conditions.size());
  for (const auto& cr : cases) {
    RegistrationRow& r = rows[static_cast<std::size_t>(cr.condition)];
    if (!cr.ok) {
      ++r.failed;
      continue;
    }
    ++r.cases;
    r.rotation_max_deg_mean += cr.rotation_error_max_deg;
    r.translation_max_mm_mean += cr.translation_error_max_mm;
    r.segmentation_precision += cr.segmentation_precision;
    r.segmentation_recall += cr.segmentation_recall;
    r.peduncle_kept += cr.peduncle_kept;
    r.body_kept += cr.body_kept;
    r.rotation_max_deg_worst = std::max(r.rotation_max_deg_worst, cr.rotation_error_max_deg);
  }
  for (auto& r : rows) {
    if (r.cases > 0) {
      r.rotation_max_deg_mean /= r.cases;
      r.translation_max_mm_mean /= r.cases;
      r.segmentation_precision /= r.cases;
      r.segmentation_recall /= r.cases;
      r.peduncle_kept /= r.cases;
      r.body_kept /= r.cases;
    }
  }
  return rows;
}

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
    if (o.resume) results[i] = read_case(refs[i].file, refs[i].key);
    if (results[i]) {
      ++outcome.reused;
    } else {
      pending.push_back(i);
    }
  }
  Progress progress(static_cast<int>(pending.size()), o.progress && !o.quiet);
  tbb::parallel_for(std::size_t{0}, pending.size(), std::size_t{1}, [&](std::size_t p) {
    const CaseRef& ref = refs[pending[p]];
    CaseResult r = run_case(set.conditions[static_cast<std::size_t>(ref.condition)], ref.condition, ref.job);
    // Written atomically as soon as it is done: an interrupted run resumes from here.
    write_file_atomic(ref.file, case_to_json(r).dump(1) + "\n");
    progress.done(r);
    results[pending[p]] = std::move(r);
  });
  outcome.computed = static_cast<int>(pending.size());
  // Other shards' cases may already be here (a shared folder); the tables need all.
  std::vector<CaseResult> cases;
  for (std::size_t i = 0; i < refs.size(); ++i) {
    if (!results[i]) results[i] = read_case(refs[i].file, refs[i].key);
    if (!results[i]) return outcome;
    cases.push_back(*results[i]);
  }
  write_outputs(set, cases, o, outcome);
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
    std::optional<CaseResult> found = read_case(ref.file, ref.key);
    for (const auto& d : shard_dirs) {
      if (found) break;
      found = read_case(d / "cases" / ref.file.filename(), ref.key);
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
                     " cases are in none of the shard folders (or were run with other parameters):" + missing +
                     (n_missing > 5 ? " ..." : ""));
  }
  write_outputs(set, cases, o, outcome);
  return outcome;
}

}  // namespace grapebench
