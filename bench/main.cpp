// grapebench: the command-line program.
#include "bench/bench_compare.h"
#include "bench/build_info.h"
#include "bench/check.h"
#include "bench/dataset_run.h"
#include "bench/scoring/coco_eval.h"
#include "bench/estimate_run.h"
#include "synth/confined_program.h"
#include "bench/runner.h"
#include "bench/scan_run.h"
#include "bench/protocols/registry.h"
#include "bench/scene_file.h"
#include "bench/stop_on_signal.h"
#include "bench/synth_run.h"
#include "synth/config.h"
#include "synth/io.h"
#include "synth/read_regular_file.h"
#include "synth/params.h"

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <iostream>
#include <sstream>

namespace {

using namespace grapebench;

std::string parameter_help() {
  std::ostringstream s;
  s << "Bunch parameters (scene-file keys under `bunches:`, or --set key=value).\n"
       "Columns: unit, allowed range, then each preset's default.\n\n";
  char line[512];
  std::snprintf(line, sizeof line, "  %-24s %-9s %-17s", "key", "unit", "range");
  s << line;
  for (const auto& p : preset_names()) {
    std::snprintf(line, sizeof line, " %-18s", p.c_str());
    s << line;
  }
  s << "\n";
  std::vector<std::vector<KeyInfo>> presets;
  for (const auto& p : preset_names()) presets.push_back(bunch_param_table().keys(preset(p)));
  for (std::size_t k = 0; k < presets[0].size(); ++k) {
    const KeyInfo& key = presets[0][k];
    std::snprintf(line, sizeof line, "  %-24s %-9s %-17s", key.key.c_str(), key.unit.c_str(), key.range.c_str());
    s << line;
    for (const auto& p : presets) {
      std::snprintf(line, sizeof line, " %-18s", p[k].default_value.c_str());
      s << line;
    }
    s << "\n      " << key.doc << "\n";
  }
  s << "\nOutputs per bunch: bunch_NNNN.json (exact ground truth), bunch_NNNN.ply and .obj\n"
       "(triangle mesh, part labels as colours; parts.mtl), and summary.csv.\n";
  return s.str();
}

// Generated from the key tables: columns are key, unit, default, allowed range.
std::string sensor_help() {
  std::ostringstream s;
  s << "Scene sections for scanning (all keys optional unless marked required).\n"
       "Columns: key, unit, default, allowed range; then the key's meaning.\n\n"
       "sensor: {type: ..., keys}\n"
    << sensor_registry().help() << "\nrig: {type: ..., keys}\n"
    << rig_registry().help() << "\nbackground:\n"
    << background_param_table().help(BackgroundSpec{}) << "\nfoliage: (leaves and canes around each bunch)\n"
    << foliage_param_table().help(FoliageParams{})
    << "\ndataset: (what `grapebench dataset` writes)\n"
    << dataset_param_table().help(DatasetParams{})
    << "\nOutputs per bunch: ground_truth.json and per view .pcd (organised, binary), .ply, _depth.png\n"
       "(16-bit mm), _rgb.png, _label.png, plus bunch_NNNN_scan.json with poses and intrinsics.\n";
  return s.str();
}

nlohmann::json read_json(const std::filesystem::path& f, const std::string& what, bool benchmark = false) {
  const std::string text = read_regular_file(f, std::size_t{256} << 20);
  try {
    return parse_json_bounded(benchmark ? benchmark_json_text(text) : text);
  } catch (const std::exception& e) {
    throw InputError(f.string() + ": not " + what + ": " + e.what());
  }
}

// `--cycles-cache`'s help, one text for run, scan and dataset; only the default differs.
std::string cycles_cache_help(const std::string& default_text) {
  return "Keep Cycles' images in this folder and reuse those it holds (`renderer: cycles`); one folder can serve "
         "several scenes, `run`, `scan` and `dataset` (default: " + default_text + ")";
}

std::string run_help() {
  const PipelineSpec defaults;  // a named object: GCC 12 warns (falsely) of a temporary's string here
  std::ostringstream s;
  s << "A scene for `run` adds to the sections of `scan` (see `grapebench scan --help`).\n"
       "Columns: key, unit, default, allowed range; then the key's meaning.\n\n"
       "protocol: how a case turns a bunch into estimates (default multi_view):\n"
    << protocol_registry().help("  ") << "\npipeline: (keys marked 'only with' apply to that protocol or setting)\n"
    << pipeline_param_table().help(defaults)
    << "    registration: protocol multi_view: a method's name, or {type: ..., keys}:\n"
    << registration_registry().help("    ")
    << "    view_filters, cloud_filters: lists of pipeline steps {type: ..., keys}, on each view (camera\n"
       "        frame) and on the registered cloud:\n"
    << filter_registry().help("    ")
    << "\nestimators: a list of {type: ..., name: column name (default: the type), keys}. Every entry also takes\n"
       "  time_budget     s      600     [0.001, 86400]  wall time of one run; past it the row fails with the reason\n"
       "  memory_budget   MB     8192    [1, 1e7]        heap held at once; past it the row fails with the reason\n"
    << estimator_registry().help()
    << "\nsweep:      {dotted.key: [values] or {from, to, step}}, e.g. sensor.noise_scale: [0, 0.5, 1, 2, 4],\n"
       "            bunches.compactness (every group), estimators[2].alpha; the run covers the product.\n\n"
       "Outputs in <out>/<scene name>/: results.csv (a row per case, estimator and quantity; deterministic),\n"
       "summary.json (scores per condition and estimator; deterministic), timings.csv/json, manifest.json,\n"
       "report.html (self-contained) and plots/*.svg; cases/*.json hold finished cases, so an interrupted run\n"
       "resumes where it stopped.\n";
  return s.str();
}

int synth_command(const std::string& scene_path, const std::string& preset_name, int count,
                  std::uint64_t seed, const std::vector<std::string>& sets, const SynthOptions& opt) {
  std::vector<BunchJob> jobs;
  if (!scene_path.empty()) {
    if (!sets.empty()) throw InputError("--set applies to --preset runs; put overrides in the scene file");
    jobs = bunch_jobs(load_scene(scene_path));
  } else {
    std::ostringstream yaml;
    yaml << "name: cli\nseed: " << seed << "\nbunches:\n  - preset: " << preset_name << "\n    count: " << count << "\n";
    Scene scene = parse_scene(yaml.str(), "command line");
    for (const auto& kv : sets) {
      const auto eq = kv.find('=');
      if (eq == std::string::npos) throw InputError("--set expects key=value, got '" + kv + "'");
      set_bunch_param(scene.groups[0].params, kv.substr(0, eq), kv.substr(eq + 1));
    }
    jobs = bunch_jobs(scene);
  }
  const auto t0 = std::chrono::steady_clock::now();
  const auto results = run_synth(jobs, opt);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << synth_summary_table(results);
  std::printf("%zu bunches in %.2f s%s%s\n", results.size(), wall, opt.out.empty() ? "" : ", written to ",
              opt.out.string().c_str());
  return 0;
}

// A subcommand: its CLI11 app, and what it does once its options are parsed (its exit
// code). Each holds its options in a state its action shares.
struct Command {
  CLI::App* app;
  std::function<int()> action;
};

// -q / -v, given before or after the subcommand (they fall through to the main app).
struct Global {
  bool quiet = false, verbose = false;
  Verbosity verbosity() const { return quiet ? Verbosity::quiet : verbose ? Verbosity::verbose : Verbosity::normal; }
};

Command synth_subcommand(CLI::App& app, const std::shared_ptr<Global>& g) {
  struct Options {
    std::string scene_path, preset_name = "table-red", out_dir = "results/synth";
    int count = 1;
    std::uint64_t seed = 1;
    std::vector<std::string> sets;
    SynthOptions opt;
  };
  auto o = std::make_shared<Options>();
  auto* synth = app.add_subcommand("synth", "Generate procedural grape bunches with exact ground truth");
  synth->add_option("scene", o->scene_path, "Scene file (YAML); without it, --preset/--count/--seed are used")
      ->check(CLI::ExistingFile);
  synth->add_option("--preset", o->preset_name, "Variety preset")
      ->check(CLI::IsMember(preset_names()))->capture_default_str();
  synth->add_option("--count", o->count, "Number of bunches")->check(CLI::Range(1, 100000))->capture_default_str();
  synth->add_option("--seed", o->seed, "Scene seed (each bunch derives its own)")->capture_default_str();
  synth->add_option("--set", o->sets, "Override a bunch parameter, key=value (repeatable)");
  synth->add_option("--out", o->out_dir, "Output folder")->capture_default_str();
  synth->add_flag("--no-mesh", [o](std::int64_t) { o->opt.write_mesh = false; }, "Write ground truth only");
  synth->add_option("--mesh-level", o->opt.mesh.sphere_subdivisions, "Icosphere subdivisions per berry")
      ->check(CLI::Range(0, 6))->capture_default_str();
  synth->add_option("--tube-sides", o->opt.mesh.tube_sides, "Sides of stem tubes")
      ->check(CLI::Range(3, 256))->capture_default_str();
  synth->add_option("--alpha-wrap", o->opt.alpha_wrap,
                    "Also a tight envelope: CGAL's alpha wrap of each bunch with this carving radius, m "
                    "in [0.0005, 0.05] (0.01: about a berry's radius; 0 = off)")
      ->check(
          [](const std::string& text) -> std::string {
            double v = -1;
            try {
              v = std::stod(text);
            } catch (const std::exception&) {
            }
            if (v == 0 || (v >= 0.0005 && v <= 0.05)) return "";
            return "--alpha-wrap: 0 (off) or a carving radius in [0.0005, 0.05] m, got " + text;
          },
          "0 or [0.0005, 0.05]")
      ->capture_default_str();
  synth->add_option("--threads", o->opt.threads, "Worker threads (0 = all cores); outputs do not depend on it")
      ->check(CLI::Range(0, 1024))->capture_default_str();
  synth->footer(parameter_help());
  return {synth, [o, g] {
            o->opt.out = o->out_dir;
            o->opt.verbosity = g->verbosity();
            return synth_command(o->scene_path, o->preset_name, o->count, o->seed, o->sets, o->opt);
          }};
}

// --shard i/N into the options.
void parse_shard(const std::string& shard, RunOptions& o) {
  if (shard.empty()) return;
  const auto slash = shard.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument("no slash");
    o.shard_index = std::stoi(shard.substr(0, slash));
    o.shard_count = std::stoi(shard.substr(slash + 1));
  } catch (const std::exception&) {
    throw InputError("--shard expects i/N (0 <= i < N), got '" + shard + "'");
  }
}

int run_command(std::vector<std::string> scenes, const std::string& out, const std::string& shard, RunOptions run_opt) {
  const bool quiet = run_opt.verbosity == Verbosity::quiet;
  if (scenes.empty()) scenes = {"scenes/default.yaml"};
  parse_shard(shard, run_opt);
  // Every scene is read (and every error reported) before any work starts.
  std::vector<SceneSet> scene_sets;
  for (const auto& path : scenes) scene_sets.push_back(load_scene_set(path));
  hide_from_programs(out);  // the cases and truth of this and other scenes' runs
  for (const auto& set : scene_sets) {
    RunOptions o = run_opt;
    o.out = std::filesystem::path(out) / set.base.name;
    if (!quiet) {
      std::printf("== %s (%s): %zu condition(s) x %zu bunches\n", set.base.name.c_str(), set.base.path.c_str(),
                  set.conditions.size(), bunch_jobs(set.base).size());
      std::fflush(stdout);
    }
    const auto t0 = std::chrono::steady_clock::now();
    const RunOutcome r = run_scene_set(set, o);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%d cases: %d computed, %d reused from %s/cases (%.1f s)\n", r.cases, r.computed, r.reused,
                o.out.string().c_str(), wall);
    if (r.tampered > 0) {
      std::printf("%d case file(s) did not match their digest (edited or damaged): recomputed\n", r.tampered);
    }
    if (r.other_build > 0) {
      std::printf("%d finished case(s) there were computed by another build (not this binary, %s): %s\n",
                  r.other_build, build_identity().c_str(),
                  o.reuse_other_builds ? "reused, as --reuse-other-builds asks" : "recomputed (--reuse-other-builds reuses them)");
    }
    if (r.complete) {
      std::cout << r.leaderboard;
      std::printf("results: %s/{results.csv,summary.json,report.html}\n", o.out.string().c_str());
    } else {
      std::printf("shard %d/%d done; join the shards with `grapebench merge %s --from <dirs> --out <dir>`\n",
                  o.shard_index, o.shard_count, set.base.path.c_str());
    }
  }
  return 0;
}

Command run_subcommand(CLI::App& app, const std::shared_ptr<Global>& g) {
  struct Options {
    std::vector<std::string> scenes;
    std::string out = "results/runs", shard;
    RunOptions run;
  };
  auto o = std::make_shared<Options>();
  auto* run =
      app.add_subcommand("run", "Run scene files: scan, register, estimate, score, report (default: scenes/default.yaml)");
  run->add_option("scenes", o->scenes, "Scene files")->check(CLI::ExistingFile);
  run->add_option("--out", o->out, "Output folder (one subfolder per scene)")->capture_default_str();
  run->add_option("--threads", o->run.threads, "Worker threads (0 = all cores); results do not depend on it")
      ->check(CLI::Range(0, 1024))->capture_default_str();
  run->add_option("--shard", o->shard, "Run only slice i of N (i/N, 0-based); join with `grapebench merge`");
  run->add_flag("--no-resume", [o](std::int64_t) { o->run.resume = false; }, "Recompute finished cases too");
  run->add_flag("--reuse-other-builds", o->run.reuse_other_builds,
                "Also reuse finished cases that another build of grapebench computed (by default they are recomputed)");
  run->add_option("--cycles-cache", o->run.cycles_cache,
                  cycles_cache_help("the scene's run folder's cycles_cache/"));
  run->footer(run_help());
  return {run, [o, g] {
            o->run.verbosity = g->verbosity();
            return run_command(o->scenes, o->out, o->shard, o->run);
          }};
}

Command merge_subcommand(CLI::App& app) {
  struct Options {
    std::string scene, out;
    std::vector<std::string> from;
    bool reuse_other_builds = false;
  };
  auto o = std::make_shared<Options>();
  auto* merge = app.add_subcommand("merge", "Join the case files of `run --shard` folders and write the tables and report");
  merge->add_option("scene", o->scene, "The scene file the shards ran")->required()->check(CLI::ExistingFile);
  merge->add_option("--from", o->from, "Shard output folders (the scene's folder in each)")->required();
  merge->add_option("--out", o->out, "Merged output folder")->required();
  merge->add_flag("--reuse-other-builds", o->reuse_other_builds,
                  "Accept cases that another build of grapebench computed");
  return {merge, [o] {
            const SceneSet set = load_scene_set(o->scene);
            RunOptions ro;
            ro.out = o->out;
            ro.reuse_other_builds = o->reuse_other_builds;
            const std::vector<std::filesystem::path> dirs(o->from.begin(), o->from.end());
            const RunOutcome r = merge_shards(set, dirs, ro);
            std::cout << r.leaderboard;
            std::printf("merged %d cases into %s\n", r.cases, o->out.c_str());
            return 0;
          }};
}

Command check_subcommand(CLI::App& app) {
  struct Options {
    std::string run, baseline;
  };
  auto o = std::make_shared<Options>();
  auto* check = app.add_subcommand("check", "Compare a run's summary.json with a baseline; exit 1 on a regression");
  check->add_option("run", o->run, "summary.json of the run (or its folder)")->required();
  check->add_option("--baseline", o->baseline, "Baseline summary (results/baseline/<suite>.json)")->required()
      ->check(CLI::ExistingFile);
  return {check, [o] {
            std::filesystem::path p = o->run;
            if (std::filesystem::is_directory(p)) p /= "summary.json";
            const auto res = check_against_baseline(read_json(p, "a summary JSON file"),
                                                    read_json(o->baseline, "a summary JSON file"), p.string(),
                                                    o->baseline);
            std::cout << res.diff;
            std::printf("%s: %d rows compared with %s\n", res.pass ? "PASS" : "REGRESSION", res.rows_compared,
                        o->baseline.c_str());
            return res.pass ? 0 : 1;
          }};
}

Command compare_bench_subcommand(CLI::App& app) {
  struct Options {
    std::string old_file, new_file;
    double threshold = 0.10;
  };
  auto o = std::make_shared<Options>();
  auto* cmp = app.add_subcommand("compare-bench", "Compare two Google Benchmark JSON files; exit 1 on a slowdown");
  cmp->add_option("baseline", o->old_file, "JSON of the reference (e.g. the previous commit)")->required()
      ->check(CLI::ExistingFile);
  cmp->add_option("contender", o->new_file, "JSON of the new build")->required()->check(CLI::ExistingFile);
  cmp->add_option("--threshold", o->threshold, "Flag ratios above 1 + threshold")->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmp->footer(
      "Run both builds on the same machine with --benchmark_repetitions=9\n"
      "--benchmark_enable_random_interleaving=true --benchmark_out=<file>.json. A benchmark is flagged\n"
      "SLOWER when the ratio of medians exceeds 1 + threshold and (with 3+ repetitions each) the\n"
      "Mann-Whitney U test gives p < 0.05.");
  return {cmp, [o] {
            if (!std::isfinite(o->threshold)) throw InputError("--threshold: a number in [0, 10], got nan");
            BenchComparison c;
            try {
              c = compare_benchmarks(read_json(o->old_file, "a Google Benchmark JSON file", true),
                                     read_json(o->new_file, "a Google Benchmark JSON file", true), o->threshold, 0.05,
                                     o->old_file, o->new_file);
            } catch (const nlohmann::json::exception& e) {
              throw InputError("compare-bench: a file lacks Google Benchmark fields: " + std::string(e.what()));
            }
            std::cout << c.table;
            return c.slower ? 1 : 0;
          }};
}

Command speed_gate_subcommand(CLI::App& app) {
  struct Options {
    std::string gate;
    std::vector<std::string> runs;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("speed-gate", "Check in-run speed ratios against their bounds; exit 1 when one is over");
  cmd->add_option("gate", o->gate, "the bounds (results/baseline/speed_gate.json)")->required()->check(CLI::ExistingFile);
  cmd->add_option("runs", o->runs, "Google Benchmark JSON files of one run")->required()->check(CLI::ExistingFile);
  cmd->footer(
      "Each ratio is median(numerator) / median(denominator) over the repetitions of the\n"
      "runs (--benchmark_repetitions, --benchmark_enable_random_interleaving). scripts/speed_gate.sh\n"
      "runs the benchmarks and this check.");
  return {cmd, [o] {
            std::vector<std::pair<std::string, nlohmann::json>> runs;
            for (const auto& f : o->runs) runs.emplace_back(f, read_json(f, "a Google Benchmark JSON file", true));
            const SpeedGateResult r = check_speed_gate(read_json(o->gate, "a speed gate JSON file"), o->gate, runs);
            std::cout << r.table;
            std::printf("%s: speed gate %s\n", r.pass ? "PASS" : "TOO SLOW", o->gate.c_str());
            return r.pass ? 0 : 1;
          }};
}

Command scan_subcommand(CLI::App& app, const std::shared_ptr<Global>& g) {
  struct Options {
    std::string scene, out = "results/scans";
    ScanRunOptions scan;
  };
  auto o = std::make_shared<Options>();
  auto* scan = app.add_subcommand("scan", "Scan a scene's bunches with its sensor and rig");
  scan->add_option("scene", o->scene, "Scene file with `sensor:` and `rig:` sections")->required()
      ->check(CLI::ExistingFile);
  scan->add_option("--out", o->out, "Output folder (one subfolder per bunch)")->capture_default_str();
  scan->add_option("--threads", o->scan.threads, "Worker threads (0 = all cores); outputs do not depend on it")
      ->check(CLI::Range(0, 1024))->capture_default_str();
  scan->add_option("--bunch", o->scan.only_bunch, "Scan only this bunch index")->check(CLI::Range(0, 100000));
  scan->add_flag("--merged", o->scan.merged, "Also write <stem>_merged.ply: every view's points in the world frame");
  scan->add_option("--cycles-cache", o->scan.cycles_cache,
                   cycles_cache_help("none; e.g. a run's results/runs/<scene>/cycles_cache"));
  scan->footer(sensor_help());
  return {scan, [o, g] {
            o->scan.verbosity = g->verbosity();
            const Scene scene = load_scene(o->scene);
            o->scan.out = std::filesystem::path(o->out) / scene.name;
            const auto rows = run_scans(scene, o->scan);
            std::cout << scan_summary_table(rows);
            std::printf("scans in %s\n", o->scan.out.string().c_str());
            return 0;
          }};
}

Command dataset_subcommand(CLI::App& app, const std::shared_ptr<Global>& g) {
  struct Options {
    std::string scene, out;
    DatasetRunOptions run;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("dataset", "Write a labelled image dataset (COCO, YOLO, depth, instances, 3D truth)");
  cmd->add_option("scene", o->scene, "Scene file with a colour `sensor:` (stereo_rgb) and a `rig:`")->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", o->out, "The dataset's folder: new or empty, or one of the same scene with --resume")
      ->required();
  cmd->add_option("--threads", o->run.threads, "Worker threads (0 = all cores); the files do not depend on it")
      ->check(CLI::Range(0, 1024))->capture_default_str();
  cmd->add_flag("--resume", o->run.resume, "Continue the dataset in --out (the same scene): finished cases are kept");
  cmd->add_option("--cycles-cache", o->run.cycles_cache,
                  cycles_cache_help("none"));
  std::ostringstream footer;
  footer << "Per image (the colour sensor's left camera), in <out>/{images,depth,instances,semantic}/<split>/:\n"
            "  colour PNG; exact depth as 16-bit PNG (mm) and float TIFF (m), 0 where nothing is hit; instance\n"
            "  IDs (16-bit PNG: the annotation's instance_id, 0 none); semantic (8-bit PNG: part + 1, 0 none:\n"
            "  1 berry, 2 pedicel, 3 rachis, 4 peduncle, 5 trellis or backdrop, 6 leaf, 7 cane).\n"
            "Per dataset: annotations/<split>.json (COCO: visible and amodal RLE masks, boxes, visible\n"
            "  fraction, intrinsics in OpenCV's convention and the camera-to-world pose per image),\n"
            "  labels/ and labels_seg/ (YOLO boxes and polygons, classes = COCO id - 1), dataset.yaml,\n"
            "  truth.json (every bunch's volume, sizes, cutting point and berries; annotations link to it\n"
            "  by bunch_uid and berry), manifest.json. Categories:\n";
  for (const auto& c : kDatasetCategories) footer << "  " << c.id << " " << c.name << ": " << c.doc << "\n";
  footer << "Splits by bunch seed (scene section `dataset:`):\n" << dataset_param_table().help(DatasetParams{});
  cmd->footer(footer.str());
  return {cmd, [o, g] {
            o->run.verbosity = g->verbosity();
            o->run.out = o->out;
            const SceneSet set = load_scene_set(o->scene);
            const DatasetSummary s = write_dataset(set, o->run);
            std::printf("%d images in %.1f s (%.2f images/s), %d cases (%d already written), %zu annotations "
                        "(train/val/test images %d/%d/%d), peak memory %.0f MB: %s\n",
                        s.images, s.seconds, s.images / std::max(s.seconds, 1e-9), s.cases + s.cases_resumed,
                        s.cases_resumed, s.annotations, s.split_images[0], s.split_images[1], s.split_images[2],
                        s.peak_rss_mb, o->out.c_str());
            if (g->verbosity() != Verbosity::quiet)
              std::printf("per image: capture %.3f s, labels %.3f s, masks %.3f s, files %.3f s\n",
                          s.timing.capture / std::max(s.images, 1), s.timing.labels / std::max(s.images, 1),
                          s.timing.masks / std::max(s.images, 1), s.timing.write / std::max(s.images, 1));
            return 0;
          }};
}

Command coco_eval_subcommand(CLI::App& app) {
  struct Options {
    std::string gt, results, iou = "bbox", json_out;
    std::vector<int> max_dets{1, 10, 100};
  };
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand("coco-eval", "Score detections (COCO results JSON) against a dataset's COCO annotations");
  cmd->add_option("annotations", o->gt, "COCO ground truth, e.g. <dataset>/annotations/test.json")->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("results", o->results, "COCO results: [{image_id, category_id, score, bbox or segmentation}]")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("--iou", o->iou, "What is compared: bbox (boxes) or segm (RLE masks)")
      ->check(CLI::IsMember({"bbox", "segm"}))->capture_default_str();
  cmd->add_option("--max-dets", o->max_dets, "COCO's three max-detections limits (berries: raise the last)")
      ->expected(3)->check(CLI::Range(1, 1000000))->capture_default_str();
  cmd->add_option("--json", o->json_out, "Also write the numbers as JSON to this file");
  cmd->footer("COCO's rules (pycocotools' COCOeval, re-implemented: bench/scoring/coco_eval.h): AP over IoU\n"
              "0.50:0.05:0.95 with 101-point interpolation, AP50, AP75, per area range (small < 32^2 px <= medium\n"
              "< 96^2 px <= large), AR at the three limits; crowd regions absorb detections. -1: undefined.");
  return {cmd, [o] {
            auto load = [](const std::string& path) {
              try {
                return nlohmann::json::parse(read_regular_file(path, std::size_t{1} << 32));
              } catch (const nlohmann::json::exception& e) {
                throw InputError(path + ": not JSON: " + e.what());
              }
            };
            const CocoIouType type = o->iou == "segm" ? CocoIouType::Segm : CocoIouType::Bbox;
            const CocoGroundTruth gt = read_coco_ground_truth(load(o->gt), o->gt);
            const std::vector<CocoObject> dets = read_coco_results(load(o->results), o->results, gt, type);
            const CocoEvalResult r = coco_evaluate(gt, dets, CocoEvalParams{type, o->max_dets});
            nlohmann::ordered_json j;
            j["iou"] = o->iou;
            j["max_dets"] = o->max_dets;
            auto stats_json = [&](const std::array<double, 12>& s) {
              nlohmann::ordered_json x;
              for (std::size_t i = 0; i < s.size(); ++i) x[coco_stat_name(i, o->max_dets)] = s[i];
              return x;
            };
            j["all"] = stats_json(r.stats);
            std::printf("%-12s", "category");
            for (std::size_t i = 0; i < kCocoStatNames.size(); ++i)
              std::printf(" %9s", coco_stat_name(i, o->max_dets).c_str());
            std::printf("\n%-12s", "all");
            for (const double x : r.stats) std::printf(" %9.3f", x);
            std::printf("\n");
            for (const auto& [cat, s] : r.per_category) {
              j["categories"][cat.name.empty() ? std::to_string(cat.id) : cat.name] = stats_json(s);
              std::printf("%-12s", cat.name.substr(0, 12).c_str());
              for (const double x : s) std::printf(" %9.3f", x);
              std::printf("\n");
            }
            if (!o->json_out.empty()) write_file_atomic(o->json_out, j.dump(1) + "\n");
            return 0;
          }};
}

Command estimate_subcommand(CLI::App& app, const std::shared_ptr<Global>& g) {
  struct Options {
    std::string cloud, scene, json_out;
    std::vector<std::string> estimators;
    int threads = 0;
  };
  auto o = std::make_shared<Options>();
  auto* est = app.add_subcommand("estimate", "Run estimators on your own point cloud (PLY or PCD, metres)");
  est->add_option("cloud", o->cloud, "Point cloud: .ply (ascii or binary) or .pcd (ascii or binary), metres, z up")
      ->required();
  est->add_option("scene", o->scene, "A scene file whose `estimators:` list to run")->check(CLI::ExistingFile);
  est->add_option("-e,--estimator", o->estimators,
                  "An estimator: a type (alpha_shape) or a mapping '{type: alpha_shape, alpha: 0.02}' (repeatable; "
                  "default: every cloud estimator with its defaults)");
  est->add_option("--json", o->json_out, "Also write the answer as JSON to this file");
  est->add_option("--threads", o->threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024))
      ->capture_default_str();
  est->footer(
      "Every value is in the harness's units (volume cm3, lengths mm); named points in the cloud's frame (m).\n"
      "Estimators and their keys: `grapebench run --help`. Example with Open3D:\n"
      "  python3 -c \"import open3d as o3d; o3d.io.write_point_cloud('scan.ply', o3d.io.read_point_cloud('in.pcd'))\"\n"
      "  grapebench estimate scan.ply -e convex_hull -e '{type: alpha_shape, alpha: 0.025}' --json scan.json");
  return {est, [o, g] {
            if (!o->scene.empty() && !o->estimators.empty()) {
              throw InputError("estimate: give a scene or --estimator, not both");
            }
            const std::vector<EstimatorSpec> specs =
                o->scene.empty() ? estimators_from_arguments(o->estimators) : estimators_from_scene(o->scene);
            const CloudFile cloud = read_cloud_file(o->cloud);
            if (cloud.points.rows() == 0) throw InputError(o->cloud + ": no points");
            const int threads = o->threads > 0 ? o->threads : static_cast<int>(tbb::info::default_concurrency());
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
            const nlohmann::ordered_json answer = estimate_cloud(cloud, o->cloud, specs, g->verbosity());
            if (!o->json_out.empty()) {
              if (std::filesystem::is_directory(o->json_out)) throw InputError("--json " + o->json_out + ": is a folder");
              write_file_atomic(o->json_out, answer.dump(1) + "\n");
            }
            std::cout << estimate_table(answer);
            if (g->verbosity() != Verbosity::quiet && !o->json_out.empty()) std::printf("written to %s\n", o->json_out.c_str());
            return 0;
          }};
}

}  // namespace

int main(int argc, char** argv) {
  stop_on_signal();  // before any thread: they inherit the signals blocked
  CLI::App app{"grapebench: benchmark harness for grape-bunch geometry estimators"};
  app.require_subcommand(1);
  // The build identity hashes the executable: only when asked (a command that fails on
  // its arguments should not read 11 MB first, 330 MB under the sanitizers).
  app.set_version_flag("--version", std::function<std::string()>([] {
                         return "grapebench " + version_string() + ", build " + build_identity();
                       }));
  auto g = std::make_shared<Global>();
  app.fallthrough();  // -q and -v work after the subcommand too
  app.add_flag("-q,--quiet", g->quiet, "Errors and results only: no progress");
  app.add_flag("-v,--verbose", g->verbose, "A progress line per item, also on a terminal");
  const std::vector<Command> commands = {synth_subcommand(app, g), run_subcommand(app, g),
                                         merge_subcommand(app),    check_subcommand(app),
                                         compare_bench_subcommand(app), speed_gate_subcommand(app),
                                         scan_subcommand(app, g),
                                         dataset_subcommand(app, g),    coco_eval_subcommand(app),
                                         estimate_subcommand(app, g)};
  if (argc > 1 && argv[1][0] != '-') {
    std::string known;
    bool found = false;
    for (const auto& cmd : commands) {
      found = found || cmd.app->get_name() == argv[1];
      known += (known.empty() ? "" : ", ") + cmd.app->get_name();
    }
    if (!found) {
      std::fprintf(stderr, "grapebench: unknown subcommand '%s'; one of: %s\n", argv[1], known.c_str());
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --help-all are "errors" with code 0; every usage error exits 2, as
    // bad input does (CLI11's own codes are 105-109).
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    for (const auto& c : commands) {
      if (c.app->parsed()) return c.action();
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "grapebench: error: %s\n", e.what());
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {
    // The user's paths (an --out that is a file, a folder that cannot be made): bad
    // input, named.
    std::fprintf(stderr, "grapebench: error: %s: %s\n", e.path1().string().c_str(), e.code().message().c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "grapebench: internal error: %s\n", e.what());
    return 3;
  }
  return 0;
}
