// grapebench: the command-line program.
#include "bench/scan_run.h"
#include "bench/scene.h"
#include "bench/synth_run.h"
#include "synth/config.h"
#include "synth/params.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
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
  std::vector<BunchParams> presets;
  for (const auto& p : preset_names()) presets.push_back(preset(p));
  for (const auto& spec : bunch_param_specs()) {
    std::ostringstream range;
    range << "[" << spec.lo << ", " << spec.hi << "]";
    std::snprintf(line, sizeof line, "  %-24s %-9s %-17s", std::string(spec.key).c_str(),
                  std::string(spec.unit).c_str(), range.str().c_str());
    s << line;
    for (const auto& p : presets) {
      std::snprintf(line, sizeof line, " %-18s", format_param(p, spec).c_str());
      s << line;
    }
    s << "\n      " << spec.doc << "\n";
  }
  s << "\nOutputs per bunch: bunch_NNNN.json (exact ground truth), bunch_NNNN.ply and .obj\n"
       "(triangle mesh, part labels as colours; parts.mtl), and summary.csv.\n";
  return s.str();
}

std::string sensor_help() {
  std::ostringstream s;
  s << "Scene sections for scanning (all keys optional unless noted):\n\n"
       "sensor:   type: one of\n";
  for (const auto& e : sensor_registry()) s << "            " << e.type << "  " << e.summary << "\n";
  s << "  kinect_v2 keys: width 512, height 424, hfov_deg 70.6 [30,120], vfov_deg 60 [20,100],\n"
       "    min_range 0.5 m [0.1,10], max_range 4.5 m [0.2,20], noise_scale 1 [0,20] (0 = ideal geometry),\n"
       "    lateral_sd_px 0.5 [0,5], max_incidence_deg 80 [10,90], supersampling 2 [1,8] (n x n rays per pixel),\n"
       "    modulation_mhz 16 [1,200], min_amplitude 0.25 [0,1], edge_filter true, edge_abs 0.015 m, edge_rel 0.02\n"
       "    axial noise sigma_z = 1.5 - 0.5 z + 0.3 z^2 + 0.1 z^1.5 theta^2/(pi/2-theta)^2 mm (Fankhauser 2015)\n"
       "  d435 keys: width 848, height 480, hfov_deg 87 [40,120], baseline 0.05 m [0.01,0.5], subpixel_sd 0.08 px [0,2],\n"
       "    disparity_step 1/32 px [0,1], max_disparity 126 px [8,1024] (MinZ = f B / max_disparity),\n"
       "    max_range 10 m, projector_x 0.025 m, projector_y 0 m, require_projector true, noise_scale 1 [0,20]\n"
       "  ideal keys: width 512, height 424, hfov_deg 70.6\n\n"
       "rig:      type: turntable | robot_pass | stereo_stations\n"
       "  turntable: views 12 [1,360], step_deg 30, distance 1.0 m, camera_height 0.75 m, bunch_top_height 0.95 m,\n"
       "    bottom_view false, bottom_distance 0.6 m  (seed 000: 12 x 30 deg at 1 m; seed 002: 8 x 45 + bottom)\n"
       "  robot_pass: frames 5, spacing 0.1 m, distance 1.5 m, height_offset 0 m, yaw_deg 0 [-80,80]  (seed 003)\n"
       "  stereo_stations: distances [0.35, 0.5, 0.65, 0.8, 0.95, 1.1] m  (seed 001)\n\n"
       "background: type none | plate | cloth, distance 0.25 m behind the bunch axis, colour [r,g,b], albedo 0.5\n\n"
       "Outputs per bunch: ground_truth.json and per view .pcd (organised, binary), .ply, _depth.png\n"
       "(16-bit mm), _rgb.png, _label.png, plus bunch_NNNN_scan.json with poses and intrinsics.\n";
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
  auto* run = app.add_subcommand("run", "Run scene files (default: the default suite)");
  std::vector<std::string> run_scenes;
  std::string run_out = "results/runs";
  int run_threads = 0;
  run->add_option("scenes", run_scenes, "Scene files")->check(CLI::ExistingFile);
  run->add_option("--out", run_out, "Output folder (one subfolder per scene)")->capture_default_str();
  run->add_option("--threads", run_threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
  run->footer(
      "Until sensors/ and the scoring harness land, `run` generates each scene's bunches,\n"
      "writes their ground truth and meshes, and prints a summary.");

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
      for (const auto& path : run_scenes) {
        const Scene scene = load_scene(path);
        SynthOptions ro;
        ro.out = std::filesystem::path(run_out) / scene.name;
        ro.threads = run_threads;
        std::printf("== scene %s (%s): %zu bunches\n", scene.name.c_str(), path.c_str(), bunch_jobs(scene).size());
        const auto t0 = std::chrono::steady_clock::now();
        const auto results = run_synth(bunch_jobs(scene), ro);
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::cout << synth_summary_table(results);
        std::printf("ground truth and meshes in %s (%.2f s)\n", ro.out.string().c_str(), wall);
      }
      return 0;
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
