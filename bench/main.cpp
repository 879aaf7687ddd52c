// grapebench: the command-line program.
#include "bench/bench_compare.h"
#include "bench/check.h"
#include "bench/runner.h"
#include "bench/scan_run.h"
#include "bench/protocols/registry.h"
#include "bench/scene_file.h"
#include "bench/synth_run.h"
#include "synth/config.h"
#include "synth/params.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>
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
    << "\nOutputs per bunch: ground_truth.json and per view .pcd (organised, binary), .ply, _depth.png\n"
       "(16-bit mm), _rgb.png, _label.png, plus bunch_NNNN_scan.json with poses and intrinsics.\n";
  return s.str();
}

nlohmann::json read_json(const std::filesystem::path& f, const std::string& what) {
  std::ifstream in(f, std::ios::binary);
  if (!in) throw InputError(f.string() + ": cannot open");
  try {
    return nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw InputError(f.string() + ": not " + what + ": " + e.what());
  }
}

std::string run_help() {
  std::ostringstream s;
  s << "A scene for `run` adds to the sections of `scan` (see `grapebench scan --help`).\n"
       "Columns: key, unit, default, allowed range; then the key's meaning.\n\n"
       "protocol: how a case turns a bunch into estimates (default multi_view):\n"
    << protocol_registry().help("  ") << "\npipeline: (keys marked 'only with' apply to that protocol or setting)\n"
    << pipeline_param_table().help(PipelineSpec{})
    << "    registration: protocol multi_view: a method's name, or {type: ..., keys}:\n"
    << registration_registry().help("    ")
    << "    view_filters, cloud_filters: lists of pipeline steps {type: ..., keys}, on each view (camera\n"
       "        frame) and on the registered cloud:\n"
    << filter_registry().help("    ") << "\nestimators: a list of {type: ..., name: column name (default: the type), keys}\n"
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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"grapebench: benchmark harness for grape-bunch geometry estimators"};
  app.require_subcommand(1);

  // grapebench synth
  auto* synth = app.add_subcommand("synth", "Generate procedural grape bunches with exact ground truth");
  std::string scene_path, preset_name = "table-red";
  int count = 1;
  std::uint64_t seed = 1;
  std::vector<std::string> sets;
  SynthOptions opt;
  std::string out_dir = "results/synth";
  synth->add_option("scene", scene_path, "Scene file (YAML); without it, --preset/--count/--seed are used")
      ->check(CLI::ExistingFile);
  synth->add_option("--preset", preset_name, "Variety preset")
      ->check(CLI::IsMember(preset_names()))->capture_default_str();
  synth->add_option("--count", count, "Number of bunches")->check(CLI::Range(1, 100000))->capture_default_str();
  synth->add_option("--seed", seed, "Scene seed (each bunch derives its own)")->capture_default_str();
  synth->add_option("--set", sets, "Override a bunch parameter, key=value (repeatable)");
  synth->add_option("--out", out_dir, "Output folder")->capture_default_str();
  synth->add_flag("--no-mesh", [&](std::int64_t) { opt.write_mesh = false; }, "Write ground truth only");
  synth->add_option("--mesh-level", opt.mesh.sphere_subdivisions, "Icosphere subdivisions per berry")
      ->check(CLI::Range(0, 6))->capture_default_str();
  synth->add_option("--tube-sides", opt.mesh.tube_sides, "Sides of stem tubes")
      ->check(CLI::Range(3, 256))->capture_default_str();
  synth->add_option("--threads", opt.threads, "Worker threads (0 = all cores); outputs do not depend on it")
      ->check(CLI::Range(0, 1024))->capture_default_str();
  synth->footer(parameter_help());

  // grapebench run
  auto* run = app.add_subcommand("run", "Run scene files: scan, register, estimate, score, report (default: scenes/default.yaml)");
  std::vector<std::string> run_scenes;
  std::string run_out = "results/runs", shard;
  RunOptions run_opt;
  run->add_option("scenes", run_scenes, "Scene files")->check(CLI::ExistingFile);
  run->add_option("--out", run_out, "Output folder (one subfolder per scene)")->capture_default_str();
  run->add_option("--threads", run_opt.threads, "Worker threads (0 = all cores); results do not depend on it")
      ->check(CLI::Range(0, 1024))->capture_default_str();
  run->add_option("--shard", shard, "Run only slice i of N (i/N, 0-based); join with `grapebench merge`");
  run->add_flag("--no-resume", [&](std::int64_t) { run_opt.resume = false; }, "Recompute finished cases too");
  run->add_flag("--quiet", run_opt.quiet, "No progress output");
  run->footer(run_help());

  // grapebench merge
  auto* merge = app.add_subcommand("merge", "Join the case files of `run --shard` folders and write the tables and report");
  std::string merge_scene, merge_out;
  std::vector<std::string> merge_from;
  merge->add_option("scene", merge_scene, "The scene file the shards ran")->required()->check(CLI::ExistingFile);
  merge->add_option("--from", merge_from, "Shard output folders (the scene's folder in each)")->required();
  merge->add_option("--out", merge_out, "Merged output folder")->required();

  // grapebench check
  auto* check = app.add_subcommand("check", "Compare a run's summary.json with a baseline; exit 1 on a regression");
  std::string check_run, check_baseline;
  check->add_option("run", check_run, "summary.json of the run (or its folder)")->required();
  check->add_option("--baseline", check_baseline, "Baseline summary (results/baseline/<suite>.json)")->required()
      ->check(CLI::ExistingFile);

  // grapebench compare-bench
  auto* cmp = app.add_subcommand("compare-bench", "Compare two Google Benchmark JSON files; exit 1 on a slowdown");
  std::string cmp_old, cmp_new;
  double cmp_threshold = 0.10;
  cmp->add_option("baseline", cmp_old, "JSON of the reference (e.g. the previous commit)")->required()->check(CLI::ExistingFile);
  cmp->add_option("contender", cmp_new, "JSON of the new build")->required()->check(CLI::ExistingFile);
  cmp->add_option("--threshold", cmp_threshold, "Flag ratios above 1 + threshold")->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmp->footer(
      "Run both builds on the same machine with --benchmark_repetitions=9\n"
      "--benchmark_enable_random_interleaving=true --benchmark_out=<file>.json. A benchmark is flagged\n"
      "SLOWER when the ratio of medians exceeds 1 + threshold and (with 3+ repetitions each) the\n"
      "Mann-Whitney U test gives p < 0.05.");

  // grapebench scan
  auto* scan = app.add_subcommand("scan", "Scan a scene's bunches with its sensor and rig");
  std::string scan_scene;
  ScanRunOptions scan_opt;
  std::string scan_out = "results/scans";
  scan->add_option("scene", scan_scene, "Scene file with `sensor:` and `rig:` sections")->required()
      ->check(CLI::ExistingFile);
  scan->add_option("--out", scan_out, "Output folder (one subfolder per bunch)")->capture_default_str();
  scan->add_option("--threads", scan_opt.threads, "Worker threads (0 = all cores); outputs do not depend on it")
      ->check(CLI::Range(0, 1024))->capture_default_str();
  scan->add_option("--bunch", scan_opt.only_bunch, "Scan only this bunch index")->check(CLI::Range(0, 100000));
  scan->footer(sensor_help());

  CLI11_PARSE(app, argc, argv);
  try {
    if (synth->parsed()) {
      opt.out = out_dir;
      return synth_command(scene_path, preset_name, count, seed, sets, opt);
    }
    if (scan->parsed()) {
      const Scene scene = load_scene(scan_scene);
      scan_opt.out = std::filesystem::path(scan_out) / scene.name;
      const auto rows = run_scans(scene, scan_opt);
      std::cout << scan_summary_table(rows);
      std::printf("scans in %s\n", scan_opt.out.string().c_str());
      return 0;
    }
    if (run->parsed()) {
      if (run_scenes.empty()) run_scenes = {"scenes/default.yaml"};
      if (!shard.empty()) {
        const auto slash = shard.find('/');
        try {
          if (slash == std::string::npos) throw std::invalid_argument("no slash");
          run_opt.shard_index = std::stoi(shard.substr(0, slash));
          run_opt.shard_count = std::stoi(shard.substr(slash + 1));
        } catch (const std::exception&) {
          throw InputError("--shard expects i/N (0 <= i < N), got '" + shard + "'");
        }
      }
      // Every scene is read (and every error reported) before any work starts.
      std::vector<SceneSet> scene_sets;
      for (const auto& path : run_scenes) scene_sets.push_back(load_scene_set(path));
      for (const auto& set : scene_sets) {
        RunOptions o = run_opt;
        o.out = std::filesystem::path(run_out) / set.base.name;
        std::printf("== %s (%s): %zu condition(s) x %zu bunches\n", set.base.name.c_str(), set.base.path.c_str(),
                    set.conditions.size(), bunch_jobs(set.base).size());
        std::fflush(stdout);
        const auto t0 = std::chrono::steady_clock::now();
        const RunOutcome r = run_scene_set(set, o);
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("%d cases: %d computed, %d reused from %s/cases (%.1f s)\n", r.cases, r.computed, r.reused,
                    o.out.string().c_str(), wall);
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
    if (merge->parsed()) {
      const SceneSet set = load_scene_set(merge_scene);
      RunOptions o;
      o.out = merge_out;
      std::vector<std::filesystem::path> dirs(merge_from.begin(), merge_from.end());
      const RunOutcome r = merge_shards(set, dirs, o);
      std::cout << r.leaderboard;
      std::printf("merged %d cases into %s\n", r.cases, merge_out.c_str());
      return 0;
    }
    if (cmp->parsed()) {
      BenchComparison c;
      try {
        c = compare_benchmarks(read_json(cmp_old, "a Google Benchmark JSON file"),
                               read_json(cmp_new, "a Google Benchmark JSON file"), cmp_threshold);
      } catch (const nlohmann::json::exception& e) {
        throw InputError("compare-bench: a file lacks Google Benchmark fields: " + std::string(e.what()));
      }
      std::cout << c.table;
      return c.slower ? 1 : 0;
    }
    if (check->parsed()) {
      std::filesystem::path p = check_run;
      if (std::filesystem::is_directory(p)) p /= "summary.json";
      const auto res = check_against_baseline(read_json(p, "a summary JSON file"),
                                              read_json(check_baseline, "a summary JSON file"));
      std::cout << res.diff;
      std::printf("%s: %d rows compared with %s\n", res.pass ? "PASS" : "REGRESSION", res.rows_compared,
                  check_baseline.c_str());
      return res.pass ? 0 : 1;
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "grapebench: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "grapebench: internal error: %s\n", e.what());
    return 3;
  }
  return 0;
}
