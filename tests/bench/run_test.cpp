// The harness: sweeps, strict estimator sections, resume, shards, determinism, check.
#include "bench/heap_meter.h"

#include "synth/io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "bench/bench_compare.h"
#include "bench/case_result.h"
#include "bench/check.h"
#include "bench/runner.h"
#include "bench/scan_run.h"
#include "sensors/render/cycles_render.h"
#include "synth/confined_program.h"
#include "file_text.h"
#include "scratch.h"
#include "scene_error.h"

namespace grapebench {
namespace {

namespace fs = std::filesystem;

// A small but real scene: 3 bunches, a 4-view ideal-free Kinect turntable, fast estimators.
const char* kScene = R"(name: tiny
seed: 5
bunches:
  - preset: summer-black
    count: 3
sensor:
  type: kinect_v2
  width: 256
  height: 212
rig:
  type: turntable
  views: 4
  step_deg: 90
estimators:
  - type: convex_hull
    name: CH
  - type: voxel
    name: VB
    voxel_size: 0.006
  - type: pca_box
)";

fs::path fresh_dir(const std::string& name) { return scratch("run_test_" + name); }

RunOptions quiet(const fs::path& out, int threads = 1) {
  RunOptions o;
  o.out = out;
  o.threads = threads;
  o.verbosity = Verbosity::quiet;
  return o;
}

TEST(Sweep, ExpandsTheProductFirstAxisSlowest) {
  const SceneSet s = parse_scene_set(std::string(kScene) +
                                         "sweep:\n  sensor.noise_scale: [0, 2]\n"
                                         "  estimators[1].voxel_size: {from: 0.004, to: 0.008, step: 0.002}\n",
                                     "s.yaml");
  ASSERT_EQ(s.conditions.size(), 6u);
  EXPECT_EQ(s.conditions[0].label, "noise_scale=0 voxel_size=0.004");
  EXPECT_EQ(s.conditions[5].label, "noise_scale=2 voxel_size=0.008");
  EXPECT_DOUBLE_EQ(s.conditions[4].scene.estimators[1].params["voxel_size"].get<double>(), 0.006);
  EXPECT_EQ(s.conditions[3].scene.sensor->describe()["noise_scale"].get<double>(), 2.0);
  // The same bunches in every condition (paired comparisons).
  EXPECT_EQ(bunch_jobs(s.conditions[0].scene)[2].seed, bunch_jobs(s.conditions[5].scene)[2].seed);
}

TEST(Sweep, BadValuesNameTheLineTheyWereWrittenOn) {
  const std::string m = scene_error(std::string(kScene) + "sweep:\n  sensor.noise_scale: [0, 1,\n     50]\n");
  EXPECT_NE(m.find("scene.yaml:23"), std::string::npos) << m;
  EXPECT_NE(m.find("[0, 20]"), std::string::npos) << m;
  EXPECT_NE(m.find("sweep point noise_scale=50"), std::string::npos) << m;
  const std::string unknown = scene_error(std::string(kScene) + "sweep:\n  sensor.nosie_scale: [0, 1]\n");
  EXPECT_NE(unknown.find("scene.yaml:22: unknown key 'sensor.nosie_scale'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("nosie_scale"), std::string::npos) << unknown;
  EXPECT_NE(scene_error(std::string(kScene) + "sweep:\n  rig.views: {from: 1, to: 4}\n").find("from, to and step"),
            std::string::npos);
  // Issue 39's reproducer: estimators[-1] was read as "every estimator", [1x] as [1].
  for (const char* key : {"estimators[-1].alpha", "estimators[1x].alpha"}) {
    const std::string e = scene_error(std::string(kScene) + "sweep:\n  " + key + ": [1, 2]\n");
    EXPECT_NE(e.find("bad index in"), std::string::npos) << key << " -> " << e;
  }
}

// Issue 23's reproducer: a list of 1,000 sweep values took 184 s to expand (2,000:
// not done after 200 s) while the same values as {from, to, step} took seconds. The
// list now expands to the conditions of the range (ctest's timeout would catch a
// relapse), in a scene whose sweep block is in the middle, with comments around it.
TEST(Sweep, ALongValueListExpandsToTheConditionsOfTheRange) {
  std::string list;
  for (int i = 0; i < 2000; ++i) list += (i ? ", " : "") + std::to_string(i);
  std::string head = kScene, tail;
  const auto at = head.find("estimators:");
  ASSERT_NE(at, std::string::npos);
  tail = head.substr(at);
  head = head.substr(0, at);
  const SceneSet listed = parse_scene_set(head + "sweep:  # the seeds\n  seed: [" + list + "]\n# after\n" + tail, "l.yaml");
  const SceneSet ranged = parse_scene_set(head + "sweep:\n  seed: {from: 0, to: 1999, step: 1}\n" + tail, "r.yaml");
  ASSERT_EQ(listed.conditions.size(), 2000u);
  ASSERT_EQ(ranged.conditions.size(), 2000u);
  for (std::size_t c = 0; c < 2000; c += 199) {
    EXPECT_EQ(listed.conditions[c].label, ranged.conditions[c].label);
    EXPECT_EQ(scene_json(listed.conditions[c].scene).dump(), scene_json(ranged.conditions[c].scene).dump());
  }
}

// An estimator over its budget is a failed row with the reason, never a hung run.
TEST(Estimators, OverBudgetRunsFailTheirRowsWithTheReason) {
  // PB_big only where the heap meter counts (not under the sanitizers): without it the
  // memory budget cannot hold, and its three full screened solves were 176 s of the
  // sanitizer stage for nothing.
  const std::string yaml = std::string(kScene) +
                           "  - type: poisson\n    name: PB_slow\n    solver: screened\n    time_budget: 0.002\n" +
                           (heap_meter_available()
                                ? "  - type: poisson\n    name: PB_big\n    solver: screened\n    memory_budget: 1\n"
                                : "") +
                           "  - type: cylinder_fit\n    name: GC_slow\n    max_iterations: 1000000\n    time_budget: 0.001\n";
  const fs::path out = fresh_dir("budgets");
  run_scene_set(parse_scene_set(yaml, "budgets.yaml"), quiet(out, 2));
  const std::string csv = slurp(out / "results.csv");
  EXPECT_NE(csv.find("over its time budget of 0.002 s (time_budget)"), std::string::npos) << csv;
  EXPECT_NE(csv.find("GC_slow,cylinder_fit,size_major,mm,NaN,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("over its time budget of 0.001 s (time_budget)"), std::string::npos) << csv;
  if (heap_meter_available()) {
    EXPECT_NE(csv.find("over its memory budget of 1 MB (memory_budget)"), std::string::npos) << csv;
  }
  // The other estimators of the same cases are untouched.
  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  for (const auto& r : summary["scores"]) {
    const std::string name = r["estimator"].get<std::string>();
    if (name == "PB_slow" || name == "GC_slow" || (name == "PB_big" && heap_meter_available())) {
      EXPECT_EQ(r["succeeded"].get<int>(), 0) << name;
    } else if (name == "CH") {
      EXPECT_EQ(r["succeeded"].get<int>(), 3) << name;
    }
  }
  const std::string m = scene_error(std::string(kScene) + "    time_budget: 0\n");
  EXPECT_NE(m.find("time_budget"), std::string::npos) << m;
}

TEST(Estimators, SectionErrorsNameFileLineKeyAndRange) {
  std::string m = scene_error(std::string(kScene) + "  - type: alpha_shape\n    alpha: 50\n");
  EXPECT_NE(m.find("scene.yaml:22"), std::string::npos) << m;
  EXPECT_NE(m.find("alpha"), std::string::npos) << m;
  EXPECT_NE(m.find("[0.0001, 10]"), std::string::npos) << m;
  m = scene_error(std::string(kScene) + "  - type: poisson_magic\n");
  EXPECT_NE(m.find("scene.yaml:21"), std::string::npos) << m;
  EXPECT_NE(m.find("allowed: pca_box"), std::string::npos) << m;
  m = scene_error(std::string(kScene) + "  - type: poisson\n    solver: screened\n    screening: -1\n");
  EXPECT_NE(m.find("screening"), std::string::npos) << m;
  EXPECT_NE(m.find("[0, 10000]"), std::string::npos) << m;
  // PCL's octree depth means nothing to the screened solver: an error naming the solver it needs.
  m = scene_error(std::string(kScene) + "  - type: poisson\n    solver: screened\n    depth: 9\n");
  EXPECT_NE(m.find("scene.yaml:23: 'estimators[3].depth': is read only with solver: pcl"), std::string::npos) << m;
  m = scene_error(std::string(kScene) + "  - type: voxel\n    voxle_size: 0.01\n");
  EXPECT_NE(m.find("unknown key 'estimators[3].voxle_size'"), std::string::npos) << m;
  m = scene_error(std::string(kScene) + "  - type: voxel\n    name: CH\n");
  EXPECT_NE(m.find("used twice"), std::string::npos) << m;
  m = scene_error(std::string(kScene) + "pipeline:\n  registration: magic\n");
  EXPECT_NE(m.find("scene.yaml:22"), std::string::npos) << m;
  EXPECT_NE(m.find("allowed: true_poses"), std::string::npos) << m;
  m = scene_error(std::string(kScene) +
               "pipeline:\n  registration:\n    type: plain_icp\n    icp:\n      max_iterations: 0\n");
  EXPECT_NE(m.find("pipeline.registration.icp.max_iterations"), std::string::npos) << m;
  EXPECT_NE(m.find("[1, 10000]"), std::string::npos) << m;
  // ICP settings mean nothing with the true poses: an error, not a silent default.
  m = scene_error(std::string(kScene) +
               "pipeline:\n  registration:\n    type: true_poses\n    icp:\n      max_iterations: 5\n");
  EXPECT_NE(m.find("scene.yaml:24: unknown key 'pipeline.registration.icp'"), std::string::npos) << m;
}

TEST(Pipeline, FilterStepsAreRegisteredAndStrict) {
  std::string m = scene_error(std::string(kScene) + "pipeline:\n  view_filters:\n    - type: median_magic\n");
  EXPECT_NE(m.find("scene.yaml:23"), std::string::npos) << m;
  EXPECT_NE(m.find("allowed: pass_through"), std::string::npos) << m;
  m = scene_error(std::string(kScene) + "pipeline:\n  cloud_filters:\n    - type: voxel_grid\n      leaf: 5\n");
  EXPECT_NE(m.find("scene.yaml:24"), std::string::npos) << m;
  EXPECT_NE(m.find("pipeline.cloud_filters[0].leaf"), std::string::npos) << m;
  EXPECT_NE(m.find("[0.0001, 1]"), std::string::npos) << m;
  m = scene_error(std::string(kScene) +
               "pipeline:\n  view_filters:\n    - type: pass_through\n      min: [0, 0, 1]\n      max: [1, 1, 0.5]\n");
  EXPECT_NE(m.find("must exceed `min`"), std::string::npos) << m;
  m = scene_error(std::string(kScene) + "pipeline:\n  cloud_filters:\n    - type: mls\n      radios: 0.01\n");
  EXPECT_NE(m.find("unknown key 'pipeline.cloud_filters[0].radios'"), std::string::npos) << m;
}

// Every return kept, then seed 000's clipping and region growing find the bunch in
// front of the plate; LCCP takes the stalk off; the label scores say how well.
TEST(Pipeline, SegmentationAndStalkRemovalAreScoredAgainstTheLabels) {
  const std::string scene = std::string(kScene) + R"(  - type: section_perimeters
background:
  type: plate
pipeline:
  segmentation: none
  view_filters:
    - type: pass_through
      min: [-0.3, -0.4, 0.5]
      max: [0.3, 0.3, 1.5]
    - type: region_growing
      cluster_tolerance: 0.04  # the half-resolution Kinect's gaps are twice as wide
  cloud_filters:
    - type: lccp_stalk_removal
)";
  const fs::path out = fresh_dir("pipeline");
  const RunOutcome r = run_scene_set(parse_scene_set(scene, "pipeline.yaml"), quiet(out));
  ASSERT_TRUE(r.complete);
  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  const auto& reg = summary["registration"][0];
  EXPECT_GT(reg["segmentation_precision_mean"].get<double>(), 0.98) << reg.dump();
  EXPECT_GT(reg["segmentation_recall_mean"].get<double>(), 0.9) << reg.dump();
  EXPECT_LT(reg["peduncle_kept_mean"].get<double>(), 0.5) << reg.dump();
  EXPECT_GT(reg["body_kept_mean"].get<double>(), 0.95) << reg.dump();
  for (const auto& row : summary["scores"]) EXPECT_EQ(row["succeeded"].get<int>(), 3) << row.dump();
  EXPECT_NE(slurp(out / "report.html").find("peduncle points kept"), std::string::npos);
}

TEST(Run, ScoresEveryEstimatorAndWritesAllFiles) {
  const fs::path out = fresh_dir("files");
  const RunOutcome r = run_scene_set(parse_scene_set(kScene, "tiny.yaml"), quiet(out));
  ASSERT_TRUE(r.complete);
  EXPECT_EQ(r.cases, 3);
  for (const char* f : {"results.csv", "timings.csv", "summary.json", "timings.json", "manifest.json", "report.html",
                        "plots/scatter_CH_volume.svg", "plots/time.svg"}) {
    EXPECT_TRUE(fs::exists(out / f)) << f;
  }
  // 3 bunches x (CH + VB + 3 box quantities) rows plus the header.
  const std::string csv = slurp(out / "results.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 3 * 5);
  // Each estimator's diagnostics reach its rows: the last column, `notes`.
  EXPECT_NE(csv.find(",region_precision,notes\n"), std::string::npos) << csv.substr(0, 400);
  EXPECT_NE(csv.find(" occupied voxels, "), std::string::npos) << csv;
  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  ASSERT_EQ(summary["scores"].size(), 5u);
  for (const auto& row : summary["scores"]) {
    EXPECT_EQ(row["succeeded"].get<int>(), 3) << row.dump();
    EXPECT_TRUE(row["rmse"].is_number()) << row.dump();
  }
  // The convex hull of a partial surface scan of a bunch exceeds its solid volume.
  EXPECT_GT(summary["scores"][0]["bias"].get<double>(), 0);
  EXPECT_NE(slurp(out / "report.html").find("<svg"), std::string::npos);
}

// pipeline.visibility_hull adds the rig's floor as a scored volume row: it contains
// the solid, so it exceeds the truth in every case; the key is range-checked and the
// row's name reserved.
TEST(Run, VisibilityHullIsAScoredFloorAboveTheTruth) {
  const std::string scene = std::string(kScene) + "pipeline:\n  visibility_hull: 0.002\n";
  const fs::path out = fresh_dir("floor");
  const RunOutcome r = run_scene_set(parse_scene_set(scene, "floor.yaml"), quiet(out));
  ASSERT_TRUE(r.complete);
  const std::string csv = slurp(out / "results.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 3 * 6);  // one more row per case
  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  bool found = false;
  for (const auto& row : summary["scores"]) {
    if (row["estimator"] != "visibility_hull") continue;
    found = true;
    EXPECT_EQ(row["succeeded"].get<int>(), 3) << row.dump();
    EXPECT_GT(row["bias"].get<double>(), 0) << row.dump();
  }
  EXPECT_TRUE(found);
  std::istringstream lines(csv);
  int floors = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.find(",visibility_hull,visibility_hull,volume,") == std::string::npos) continue;
    ++floors;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) f.push_back(cell);
    EXPECT_GT(std::stod(f[9]), std::stod(f[10])) << line;  // estimate > truth
  }
  EXPECT_EQ(floors, 3);
  std::string m = scene_error(std::string(kScene) + "pipeline:\n  visibility_hull: 0.00001\n");
  EXPECT_NE(m.find("scene.yaml:22"), std::string::npos) << m;
  EXPECT_NE(m.find("[1e-4, 0.05]"), std::string::npos) << m;
  m = scene_error(std::string(kScene) + "pipeline:\n  visibility_hull: 0.5\n");
  EXPECT_NE(m.find("visibility_hull"), std::string::npos) << m;
  m = scene_error(std::string(kScene) + "  - type: convex_hull\n    name: visibility_hull\n");
  EXPECT_NE(m.find("reserved"), std::string::npos) << m;
}

// PB's `orient: facing` turns each normal toward the camera that saw its point; the
// harness carries every point's view through registration and the cloud filters.
// The right viewpoints fix the berry sides facing into the bunch, which seed 000's
// centroid rule gets wrong.
TEST(Run, PoissonFacingGetsEachPointsCameraThroughTheFilters) {
  const std::string scene = std::string(kScene) + R"(  - type: poisson
    name: PB_centroid
    solver: screened
  - type: poisson
    name: PB_facing
    solver: screened
    orient: facing
pipeline:
  cloud_filters:
    - type: voxel_grid
      leaf: 0.002
)";
  const fs::path out = fresh_dir("facing");
  const RunOutcome r = run_scene_set(parse_scene_set(scene, "facing.yaml"), quiet(out));
  ASSERT_TRUE(r.complete);
  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  std::map<std::string, nlohmann::json> by_name;
  for (const auto& row : summary["scores"]) by_name[row["estimator"].get<std::string>()] = row;
  ASSERT_TRUE(by_name.count("PB_centroid") && by_name.count("PB_facing"));
  for (const char* name : {"PB_centroid", "PB_facing"})
    EXPECT_EQ(by_name[name]["succeeded"].get<int>(), 3) << by_name[name].dump();
  const double centroid = by_name["PB_centroid"]["rmse"].get<double>(),
               facing = by_name["PB_facing"]["rmse"].get<double>();
  std::printf("[facing] PB screened on 3 four-view scans: RMSE %.1f cm3 centroid, %.1f cm3 facing\n", centroid, facing);
  // Measured: 255 against 371 cm3. Every viewpoint at the frame's origin (a wrong
  // frame) gives 310, which this bound rejects.
  EXPECT_LT(facing, 0.8 * centroid);
  const std::string m = scene_error(std::string(kScene) + "  - type: poisson\n    orient: inward\n");
  EXPECT_NE(m.find("orient"), std::string::npos) << m;
  EXPECT_NE(m.find("facing"), std::string::npos) << m;
}

TEST(Run, InterruptedRunsResumeToTheSameResultsAndThreadsDoNotMatter) {
  const SceneSet set = parse_scene_set(kScene, "tiny.yaml");
  const fs::path a = fresh_dir("whole"), b = fresh_dir("resumed");
  run_scene_set(set, quiet(a, 1));
  // A run killed after one case: only that case file exists (plus a stray temp file).
  run_scene_set(set, quiet(b, 2));
  const std::string results = slurp(b / "results.csv");
  for (const auto& e : fs::directory_iterator(b / "cases")) {
    if (e.path().filename() != "c0000_b0001.json") fs::remove(e.path());
  }
  fs::remove(b / "results.csv");
  { std::ofstream(b / "cases" / "c0000_b0002.json.tmp") << "{ half"; }
  const RunOutcome r = run_scene_set(set, quiet(b, 2));
  EXPECT_EQ(r.reused, 1);
  EXPECT_EQ(r.computed, 2);
  EXPECT_EQ(slurp(b / "results.csv"), slurp(a / "results.csv"));
  EXPECT_EQ(slurp(b / "summary.json"), slurp(a / "summary.json"));
  // A damaged case file is recomputed, not read.
  { std::ofstream(b / "cases" / "c0000_b0000.json") << "{\"format\": \"grapebench-case-1\", \"key\""; }
  EXPECT_EQ(run_scene_set(set, quiet(b, 2)).computed, 1);
  EXPECT_EQ(slurp(b / "results.csv"), results);
}

// Reproducer: a failed row's NaN estimate is written as null, and reading null as a
// double threw, so every case with such a row (most stereo_pair cases) was recomputed
// on resume instead of reused.
// A run keeps Cycles' images in its folder's cycles_cache/ (sensors/render/cycles_render.h):
// run again from scratch (--no-resume) with a Blender that now crashes, every image is
// read from there and the results are the first run's. The Blender is a fake writing
// black images of the right size (the wiring is tested, not Cycles). Then the cache
// given to another run folder and to a scan (--cycles-cache): read, not rendered.
TEST(Run, ARunRendersNoCyclesImageTwice) {
  if (std::system("bwrap --ro-bind / / --dev /dev --proc /proc --unshare-all true >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "bubblewrap cannot make namespaces here (Blender runs under it)";
  const fs::path out = fresh_dir("cycles_cache");
  const fs::path bin = fresh_dir("cycles_cache_bin");
  fs::create_directories(bin);
  fs::copy_file(GRAPEBENCH_SOURCE_DIR "/tests/bench/data/fake_blender.sh", bin / "blender");
  fs::permissions(bin / "blender", fs::perms::owner_all);
  setenv("GRAPEBENCH_BLENDER", (bin / "blender").c_str(), 1);
  const SceneSet set = load_scene_set(GRAPEBENCH_SOURCE_DIR "/tests/bench/data/cycles_pair_tiny.yaml");
  EXPECT_EQ(run_scene_set(set, quiet(out)).computed, 1);
  const std::string first = slurp(out / "results.csv");
  EXPECT_EQ(std::distance(fs::directory_iterator(out / "cycles_cache"), fs::directory_iterator()), 4);  // a pair, 2 files an image
  std::ofstream(bin / "crash") << "";
  RunOptions again = quiet(out);
  again.resume = false;
  EXPECT_EQ(run_scene_set(set, again).computed, 1);
  EXPECT_EQ(slurp(out / "results.csv"), first);
  EXPECT_EQ(first.find("Blender"), std::string::npos) << first;
  // One cache serves another run folder and a scan of the same scene (--cycles-cache):
  // the key is what Blender is given, not where the images go. Without it the scan
  // needs Blender, which crashes.
  const fs::path other = fresh_dir("cycles_cache_other"), shared = fresh_dir("cycles_cache_shared");
  fs::copy(out / "cycles_cache", shared);
  RunOptions elsewhere = quiet(other);
  elsewhere.cycles_cache = shared;
  EXPECT_EQ(run_scene_set(set, elsewhere).computed, 1);
  EXPECT_EQ(slurp(other / "results.csv"), first);
  EXPECT_FALSE(fs::exists(other / "cycles_cache"));
  EXPECT_TRUE(cycles_cache().empty());  // the folder before the run is back
  // Its object-index images are per-berry truth: hidden from programs as the run folder
  // is, so no program's `readable` may show it (review of 3ac22e2: a folder outside
  // --out was not).
  const fs::path peek = fresh_dir("cycles_cache_peek");
  fs::create_directories(peek);
  try {
    ProgramLimits limits;
    limits.readable = {shared};
    ConfinedProgram ls({"/bin/ls", "-R", "/tmp"}, peek, limits);
    ls.wait(ConfinedProgram::Clock::now() + std::chrono::seconds(30));
    ADD_FAILURE() << "a program was shown the shared cache";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("no program may see"), std::string::npos) << e.what();
  }
  ScanRunOptions scan;
  scan.out = fresh_dir("cycles_cache_scan");
  scan.verbosity = Verbosity::quiet;
  EXPECT_THROW(run_scans(set.conditions.at(0).scene, scan), std::exception);
  scan.cycles_cache = shared;
  EXPECT_NO_THROW(run_scans(set.conditions.at(0).scene, scan));
  EXPECT_EQ(std::distance(fs::directory_iterator(shared), fs::directory_iterator()), 4);
  unsetenv("GRAPEBENCH_BLENDER");
}

// Issue 38, item 9: a Blender that crashes fails its case with a row per estimator
// carrying the reason (the case had no row at all, so results.csv was silent about
// it); a Blender that is not there stops the run before any case, naming the package.
TEST(Run, ACrashedBlenderIsAFailedRowAndAMissingOneStopsTheRun) {
  if (std::system("bwrap --ro-bind / / --dev /dev --proc /proc --unshare-all true >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "bubblewrap cannot make namespaces here (Blender runs under it)";
  const fs::path out = fresh_dir("cycles_crash"), bin = fresh_dir("cycles_crash_bin");
  fs::create_directories(bin);
  fs::copy_file(GRAPEBENCH_SOURCE_DIR "/tests/bench/data/fake_blender.sh", bin / "blender");
  fs::permissions(bin / "blender", fs::perms::owner_all);
  std::ofstream(bin / "crash") << "";
  setenv("GRAPEBENCH_BLENDER", (bin / "blender").c_str(), 1);
  const SceneSet set = load_scene_set(GRAPEBENCH_SOURCE_DIR "/tests/bench/data/cycles_pair_tiny.yaml");
  EXPECT_EQ(run_scene_set(set, quiet(out)).computed, 1);
  const std::string csv = slurp(out / "results.csv");
  EXPECT_NE(csv.find(",luo_eq6,luo2016_stereo,case,-,NaN,NaN,NaN,NaN,0,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\"case failed: cycles: Blender failed (killed by signal 11"), std::string::npos) << csv;
  setenv("GRAPEBENCH_BLENDER", (bin / "absent").c_str(), 1);
  const fs::path none = fresh_dir("cycles_missing");
  try {
    run_scene_set(set, quiet(none));
    ADD_FAILURE() << "a run without Blender went on";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Debian package `blender`"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(none / "cases"));
  // Its cases all reused, a run needs no Blender.
  EXPECT_EQ(run_scene_set(set, quiet(out)).reused, 1);
  unsetenv("GRAPEBENCH_BLENDER");
}

TEST(Run, ACaseWithAFailedRowsNanEstimateReadsBack) {
  CaseResult c;
  c.key = "k";
  EstimateRow row;
  row.estimator = "luo";
  row.type = "luo2016_stereo";
  row.quantity = "berry_precision";
  row.estimate = std::nan("");
  row.truth = 1;
  row.error = "no berry detected";
  c.rows.push_back(row);
  const nlohmann::ordered_json j = case_to_json(c);
  const nlohmann::json file = nlohmann::json::parse(j.dump());
  ASSERT_TRUE(file.at("rows").at(0).at("estimate").is_null());
  const CaseResult back = case_from_json(file);
  ASSERT_EQ(back.rows.size(), 1u);
  EXPECT_TRUE(std::isnan(back.rows[0].estimate));
  EXPECT_EQ(back.rows[0].error, "no berry detected");
  // An ok row must still have a finite estimate.
  c.rows[0].ok = true;
  EXPECT_THROW(case_from_json(nlohmann::json::parse(case_to_json(c).dump())), std::exception);
}

// The pixel noise a case keeps: NaN (a class without inner pixels) written as null and
// read back; a case file with a value outside [0, 255] or of the wrong size refused.
TEST(Run, ACasesPixelNoiseReadsBackAndABadOneIsRefused) {
  CaseResult c;
  c.key = "k";
  c.pixel_noise_dn = {2.5, 2.9, 2.4, std::nan(""), std::nan(""), std::nan(""), 2.0, 2.1, 2.0};
  const nlohmann::json file = nlohmann::json::parse(case_to_json(c).dump());
  ASSERT_TRUE(file.at("pixel_noise_dn").at(3).is_null());
  const CaseResult back = case_from_json(file);
  ASSERT_EQ(back.pixel_noise_dn.size(), 9u);
  EXPECT_DOUBLE_EQ(back.pixel_noise_dn[1], 2.9);
  EXPECT_TRUE(std::isnan(back.pixel_noise_dn[4]));
  nlohmann::json bad = file;
  bad["pixel_noise_dn"][0] = -1.0;
  EXPECT_THROW(case_from_json(bad), std::exception);
  bad = file;
  bad["pixel_noise_dn"].erase(8);
  EXPECT_THROW(case_from_json(bad), std::exception);
}

TEST(Run, TwoShardsMergedEqualTheUnshardedRun) {
  const SceneSet set = parse_scene_set(kScene, "tiny.yaml");
  const fs::path whole = fresh_dir("unsharded"), s0 = fresh_dir("shard0"), s1 = fresh_dir("shard1"),
                 merged = fresh_dir("merged");
  run_scene_set(set, quiet(whole));
  RunOptions o0 = quiet(s0), o1 = quiet(s1);
  o0.shard_count = o1.shard_count = 2;
  o1.shard_index = 1;
  const RunOutcome r0 = run_scene_set(set, o0);
  EXPECT_FALSE(r0.complete);
  EXPECT_EQ(r0.computed, 2);
  EXPECT_EQ(run_scene_set(set, o1).computed, 1);
  EXPECT_THROW(merge_shards(set, {s0}, quiet(merged)), InputError);  // shard 1 missing
  merge_shards(set, {s0, s1}, quiet(merged));
  EXPECT_EQ(slurp(merged / "results.csv"), slurp(whole / "results.csv"));
  EXPECT_EQ(slurp(merged / "summary.json"), slurp(whole / "summary.json"));
}

TEST(Check, FailsOnAPerturbedBaselineAndPassesOnTheTrueOne) {
  const fs::path out = fresh_dir("check");
  run_scene_set(parse_scene_set(kScene, "tiny.yaml"), quiet(out));
  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  const CheckResult same = check_against_baseline(summary, summary);
  EXPECT_TRUE(same.pass) << same.diff;
  EXPECT_EQ(same.rows_compared, 5);
  // A baseline that was better than this run (RMSE 20 % lower): a regression.
  nlohmann::json better = summary;
  better["scores"][1]["rmse"] = summary["scores"][1]["rmse"].get<double>() * 0.8;
  const CheckResult worse = check_against_baseline(summary, better);
  EXPECT_FALSE(worse.pass);
  EXPECT_NE(worse.diff.find("VB volume: RMSE"), std::string::npos) << worse.diff;
  // A row that disappeared is a regression too; one that is new is not.
  nlohmann::json fewer = summary;
  fewer["scores"].erase(0);
  EXPECT_TRUE(check_against_baseline(summary, fewer).pass);
  EXPECT_FALSE(check_against_baseline(fewer, summary).pass);
}

// Issue 39's reproducers: `check` passed with a baseline holding a key twice (the last
// won), a tolerance of 1e308 or null. Each is refused, naming the key and the range.
TEST(Check, BaselinesWithDuplicateKeysOrToleranceOutOfRangeAreRefused) {
  EXPECT_THROW((void)parse_json_bounded(R"({"scene": "a", "scores": [], "scene": "b"})"), std::runtime_error);
  EXPECT_THROW((void)parse_json_bounded(R"({"scores": [{"rmse": 1, "rmse": 2}]})"), std::runtime_error);
  EXPECT_NO_THROW((void)parse_json_bounded(R"({"a": {"x": 1}, "b": {"x": 1}})"));
  const auto summary = nlohmann::json::parse(
      R"({"scene": "s", "scores": [{"condition": "", "estimator": "CH", "quantity": "volume", "rmse": 1}]})");
  for (const char* t : {R"({"rmse_rel": 1e308})", R"({"rmse_rel": null})", R"({"success_rate_abs": -0.1})",
                        R"({"success_rate_abs": 1.5})"}) {
    nlohmann::json baseline = summary;
    baseline["tolerances"] = nlohmann::json::parse(t);
    std::string error;
    try {
      (void)check_against_baseline(summary, baseline, "run", "base.json");
    } catch (const InputError& e) {
      error = e.what();
    }
    EXPECT_NE(error.find("base.json: 'tolerances."), std::string::npos) << t << " -> " << error;
    EXPECT_NE(error.find("must be a number in [0, "), std::string::npos) << t << " -> " << error;
  }
  // Found by the 10-minute fuzz run of baseline_fuzz: a classification row whose
  // quantity is an integer (a key may be one) ended `check` with a type_error, exit 3.
  const auto integer_key = nlohmann::json::parse(
      R"({"scene": "s", "scores": [], "classification": [{"condition": "all", "estimator": "colour",
          "quantity": 7516688919, "mean": 0.9}]})");
  EXPECT_TRUE(check_against_baseline(integer_key, integer_key, "run", "base.json").pass);
}

// The per-protocol gates (scripts/regression_gate.sh): seed 004's classification rows
// and seed 001's stereo tables are compared too, each metric in its direction.
TEST(Check, GatesClassificationRowsAndStereoTables) {
  const nlohmann::json base = nlohmann::json::parse(R"({
    "scene": "g", "scores": [],
    "classification": [
      {"condition": "all", "estimator": "s2", "quantity": "auc_berry", "cases": 2, "mean": 0.95},
      {"condition": "all", "estimator": "s2", "quantity": "berry_fpr", "cases": 2, "mean": 0.10}],
    "stereo": {
      "cut_success": [{"condition": "light=front", "estimator": "luo", "pairs": 12, "successes": 8, "rate": 0.6667}],
      "depth": [{"estimator": "luo", "depth_mm": 500, "found_rate": 0.27, "ez_mm": 3.0, "ex_mm": 0.4}]},
    "tolerances": {"classification_abs": 0.01, "stereo_rate_abs": 0.05, "cut_error_mm_abs": 1.0}})");
  const CheckResult same = check_against_baseline(base, base);
  EXPECT_TRUE(same.pass) << same.diff;
  EXPECT_EQ(same.rows_compared, 4);
  const auto worse = [&](const std::string& pointer, double v, const std::string& says) {
    nlohmann::json run = base;
    run[nlohmann::json::json_pointer(pointer)] = v;
    const CheckResult r = check_against_baseline(run, base);
    EXPECT_FALSE(r.pass) << pointer;
    EXPECT_NE(r.diff.find(says), std::string::npos) << r.diff;
  };
  worse("/classification/0/mean", 0.93, "classification all s2 auc_berry: mean 0.95 -> 0.93");
  worse("/classification/1/mean", 0.12, "berry_fpr: mean 0.1 -> 0.12");  // lower is better
  worse("/stereo/cut_success/0/rate", 0.5833, "stereo.cut_success light=front luo: rate");
  worse("/stereo/depth/0/found_rate", 0.2, "stereo.depth luo 500: found_rate");
  worse("/stereo/depth/0/ez_mm", 4.5, "ez_mm 3 -> 4.5 mm");
  // Within the tolerances, or better: passes.
  nlohmann::json close = base;
  close["classification"][0]["mean"] = 0.945;
  close["classification"][1]["mean"] = 0.05;
  close["stereo"]["depth"][0]["ez_mm"] = 3.9;
  EXPECT_TRUE(check_against_baseline(close, base).pass) << check_against_baseline(close, base).diff;
  // A row missing from the run fails; an unknown tolerance is an error naming it.
  nlohmann::json fewer = base;
  fewer["stereo"]["cut_success"] = nlohmann::json::array();
  EXPECT_FALSE(check_against_baseline(fewer, base).pass);
  nlohmann::json typo = base;
  typo["tolerances"]["classifcation_abs"] = 0.1;
  try {
    check_against_baseline(base, typo, "run", "b.json");
    ADD_FAILURE() << "an unknown tolerance key passed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("b.json: 'tolerances.classifcation_abs' is not a tolerance"), std::string::npos)
        << e.what();
  }
}

TEST(CompareBench, FlagsASlowdownByRatioAndUTest) {
  const auto file = [](double scale, double other) {
    nlohmann::json j;
    j["benchmarks"] = nlohmann::json::array();
    for (int r = 0; r < 5; ++r) {
      j["benchmarks"].push_back({{"name", "BM_A"},
                                 {"run_name", "BM_A"},
                                 {"run_type", "iteration"},
                                 {"real_time", scale * (10 + 0.1 * r)},
                                 {"time_unit", "ms"}});
      j["benchmarks"].push_back({{"name", "BM_B"},
                                 {"run_name", "BM_B"},
                                 {"run_type", "iteration"},
                                 {"real_time", other * (5 + 0.1 * r)},
                                 {"time_unit", "ms"}});
    }
    j["benchmarks"].push_back({{"name", "BM_A_mean"},
                               {"run_name", "BM_A"},
                               {"run_type", "aggregate"},
                               {"real_time", 1e9},
                               {"time_unit", "ms"}});
    return j;
  };
  const BenchComparison same = compare_benchmarks(file(1, 1), file(1.02, 1), 0.1);
  EXPECT_FALSE(same.slower) << same.table;
  const BenchComparison slow = compare_benchmarks(file(1, 1), file(1, 1.5), 0.1);
  EXPECT_TRUE(slow.slower) << slow.table;
  EXPECT_NE(slow.table.find("SLOWER"), std::string::npos);
  EXPECT_EQ(slow.table.find("BM_A                                         10"),
            std::string::npos);  // aggregates ignored
}

// Issue 39's compare-bench findings: a missing time_unit was read as ns (a slowdown
// in ms reported faster), failed repetitions were timed, one repetition gave SLOWER
// with p = nan, and errors named "baseline" rather than the file.
TEST(CompareBench, RefusesMissingUnitsSkipsFailedRepetitionsAndJudgesNothingOnOne) {
  // json::array(): a one-element brace list is a copy of that element under clang.
  const auto entry = [](double ms) {
    return nlohmann::json{{"name", "BM_A"}, {"run_name", "BM_A"}, {"run_type", "iteration"}, {"real_time", ms},
                          {"time_unit", "ms"}};
  };
  nlohmann::json one_old, one_new;
  one_old["benchmarks"] = nlohmann::json::array({entry(10)});
  one_new["benchmarks"] = nlohmann::json::array({entry(20)});
  const BenchComparison one = compare_benchmarks(one_old, one_new, 0.1);
  EXPECT_FALSE(one.slower) << one.table;
  EXPECT_NE(one.table.find("under 3 repetitions"), std::string::npos) << one.table;
  // A repetition with error_occurred is not a time: the two left are equal.
  nlohmann::json old_reps, new_reps;
  old_reps["benchmarks"] = nlohmann::json::array({entry(10), entry(10.1), entry(9.9)});
  new_reps["benchmarks"] = nlohmann::json::array({entry(10), entry(10.1), entry(9.9), entry(500)});
  new_reps["benchmarks"][3]["error_occurred"] = true;
  const BenchComparison skipped = compare_benchmarks(old_reps, new_reps, 0.1);
  EXPECT_FALSE(skipped.slower) << skipped.table;
  EXPECT_NE(skipped.table.find("same"), std::string::npos) << skipped.table;
  nlohmann::json no_unit = old_reps;
  no_unit["benchmarks"][1].erase("time_unit");
  try {
    compare_benchmarks(old_reps, no_unit, 0.1, 0.05, "a.json", "b.json");
    ADD_FAILURE() << "an entry without time_unit was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("b.json: benchmark 'BM_A': no time_unit"), std::string::npos) << e.what();
  }
}

TEST(External, TheOpen3dExampleRunsThroughTheProtocol) {
  // Open3D's hull of the same points must agree with CGAL's; a program that fails or
  // answers without the quantity marks its rows failed, with the reason.
  const std::string script = std::string(GRAPEBENCH_SOURCE_DIR) + "/scripts/external/open3d_estimator.py";
  const std::string yaml =
      std::string(kScene) + "  - type: external\n    name: o3d_hull\n    command: [/usr/bin/python3, " + script +
      ", --method, convex_hull]\n"
      "  - type: external\n    name: broken\n    command: [/bin/sh, -c, 'echo no luck >&2; exit 3', sh]\n"
      "  - type: external\n    name: silent\n    command: [/bin/true]\n    quantities: [volume, height]\n";
  const fs::path out = fresh_dir("external");
  run_scene_set(parse_scene_set(yaml, "ext.yaml"), quiet(out, 2));
  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  std::map<std::string, nlohmann::json> by_name;
  for (const auto& r : summary["scores"])
    by_name[r["estimator"].get<std::string>() + "/" + r["quantity"].get<std::string>()] = r;
  ASSERT_EQ(by_name["o3d_hull/volume"]["succeeded"].get<int>(), 3) << slurp(out / "results.csv");
  EXPECT_NEAR(by_name["o3d_hull/volume"]["rmse"].get<double>(), by_name["CH/volume"]["rmse"].get<double>(), 1e-3);
  EXPECT_EQ(by_name["broken/volume"]["succeeded"].get<int>(), 0);
  EXPECT_EQ(by_name["silent/height"]["succeeded"].get<int>(), 0);
  const std::string csv = slurp(out / "results.csv");
  EXPECT_NE(csv.find("failed (exit status 3): no luck"), std::string::npos) << csv;
  EXPECT_NE(csv.find("wrote no answer.json"), std::string::npos) << csv;
  // Scene errors of the external entry name the line.
  const std::string m =
      scene_error(std::string(kScene) + "  - type: external\n    quantities: [mass]\n    command: [x]\n");
  EXPECT_NE(m.find("scene.yaml:22"), std::string::npos) << m;
  EXPECT_NE(m.find("'estimators[3].quantities': unknown value 'mass'; allowed: volume"), std::string::npos) << m;
}

// The rows of one estimator in results.csv: (case key, quantity) -> estimate, and
// its notes.
struct EstimatorRows {
  std::map<std::string, double> estimate;
  std::vector<std::string> notes;
};
EstimatorRows rows_of(const std::string& csv, const std::string& estimator) {
  EstimatorRows out;
  std::istringstream in(csv);
  std::string line, header;
  std::getline(in, header);
  std::vector<std::string> names;
  std::stringstream hs(header);
  for (std::string f; std::getline(hs, f, ',');) names.push_back(f);
  const auto col = [&](const std::string& n) {
    return static_cast<std::size_t>(std::find(names.begin(), names.end(), n) - names.begin());
  };
  while (std::getline(in, line)) {
    // Split on commas outside quotes.
    std::vector<std::string> f(1);
    bool quoted = false;
    for (char ch : line) {
      if (ch == '"')
        quoted = !quoted;
      else if (ch == ',' && !quoted)
        f.emplace_back();
      else
        f.back() += ch;
    }
    if (f[col("estimator")] != estimator) continue;
    const std::string key = f[col("condition")] + "/" + f[col("bunch")] + "/" + f[col("frame")] + "/" + f[col("roi")] +
                            "/" + f[col("region")] + "/" + f[col("quantity")];
    out.estimate[key] = f[col("estimate")] == "NaN" ? std::nan("") : std::stod(f[col("estimate")]);
    out.notes.push_back(f[col("notes")]);
  }
  return out;
}

// Two entries of the example program through protocol 2, per case and persistent,
// and two of a program that validates every request against the protocol's schema.
std::string v2_entries(const std::string& quantities, const std::string& method) {
  const std::string source = GRAPEBENCH_SOURCE_DIR, script = source + "/scripts/external/open3d_estimator.py";
  std::string s;
  for (const char* mode : {"per_case", "persistent"}) {
    const bool persistent = std::string(mode) == "persistent";
    s += std::string("  - type: external\n    name: schema_") + mode + "\n    version: 2\n" +
         (persistent ? "    persistent: true\n" : "") + "    quantities: " + quantities +
         "\n    command: [/usr/bin/python3, " + source + "/tests/bench/data/schema_check.py, " + source +
         "/docs/external-protocol.schema.json" + (persistent ? ", --persistent" : "") + "]\n";
  }
  for (const char* mode : {"per_case", "persistent"}) {
    const bool persistent = std::string(mode) == "persistent";
    s += std::string("  - type: external\n    name: v2_") + mode + "\n    version: 2\n" +
         (persistent ? "    persistent: true\n" : "") + "    quantities: " + quantities +
         "\n    command: [/usr/bin/python3, " + script + ", --method, " + method +
         (persistent ? ", --persistent" : "") + "]\n";
  }
  return s;
}

// Every request the schema checker got conformed to docs/external-protocol.schema.json.
void expect_schema_ok(const std::string& csv) {
  for (const char* name : {"schema_per_case", "schema_persistent"}) {
    const EstimatorRows rows = rows_of(csv, name);
    ASSERT_FALSE(rows.notes.empty()) << name;
    for (const auto& n : rows.notes) EXPECT_NE(n.find("schema ok: grapebench-estimator-2"), std::string::npos) << n;
    for (const auto& [key, v] : rows.estimate) EXPECT_FALSE(std::isnan(v)) << name << " " << key << "\n" << csv;
  }
}

// Each estimator's median time per run, for the log (not a pass criterion).
void print_timings(const fs::path& out, const char* protocol) {
  for (const auto& t : nlohmann::json::parse(slurp(out / "timings.json"))) {
    std::printf("[external] %s %-24s median %.1f ms per run\n", protocol, t["estimator"].get<std::string>().c_str(),
                t["median_s"].get<double>() * 1e3);
  }
}

void expect_same_rows(const EstimatorRows& a, const EstimatorRows& b, double rel, const std::string& what) {
  ASSERT_FALSE(a.estimate.empty()) << what;
  ASSERT_EQ(a.estimate.size(), b.estimate.size()) << what;
  for (const auto& [key, v] : a.estimate) {
    ASSERT_TRUE(b.estimate.count(key)) << what << " " << key;
    const double w = b.estimate.at(key);
    if (std::isnan(v) || std::isnan(w)) {
      EXPECT_EQ(std::isnan(v), std::isnan(w)) << what << " " << key;
      continue;
    }
    EXPECT_NEAR(v, w, rel * std::abs(w)) << what << " " << key;
  }
}

// The two horizontal principal extents of each case as (larger, smaller). Where a
// bunch's two largest variances nearly tie, which axis comes first is a matter of
// rounding: numpy and Eigen (built by clang, not by GCC) ordered one case apart.
EstimatorRows extents_in_order(EstimatorRows rows) {
  for (auto& [key, v] : rows.estimate) {
    const std::size_t cut = key.rfind("/length");
    if (cut == std::string::npos || cut + 7 != key.size()) continue;
    const auto width = rows.estimate.find(key.substr(0, cut) + "/width");
    if (width == rows.estimate.end()) continue;
    if (v < width->second) std::swap(v, width->second);
  }
  return rows;
}

// Protocol 2 on the multi_view protocol: the program gets the registered cloud with
// normals, viewpoints and colours, and the views with their poses; its hull and
// principal extents equal the built-ins' on the same points, per case and persistent.
TEST(External, ProtocolTwoOnMultiViewPerCaseAndPersistent) {
  const std::string yaml = std::string(kScene) + v2_entries("[volume, height, length, width]", "convex_hull");
  const fs::path out = fresh_dir("external_v2_multi_view");
  run_scene_set(parse_scene_set(yaml, "ext2.yaml"), quiet(out, 2));
  const std::string csv = slurp(out / "results.csv");
  const EstimatorRows per_case = rows_of(csv, "v2_per_case"), persistent = rows_of(csv, "v2_persistent");
  expect_same_rows(per_case, persistent, 0, "persistent vs per case");
  expect_schema_ok(csv);
  EstimatorRows builtin = rows_of(csv, "CH");
  for (const auto& [k, v] : rows_of(csv, "pca_box").estimate) builtin.estimate[k] = v;
  expect_same_rows(extents_in_order(per_case), extents_in_order(builtin), 1e-6, "Open3D/numpy vs CGAL hull and PCA box");
  for (const auto& n : persistent.notes) {
    EXPECT_NE(n.find("grapebench-estimator-2, multi_view, 4 views, normals+viewpoints+colours"), std::string::npos)
        << n;
  }
  print_timings(out, "multi_view");
}

// Protocol 2 on the single_frame protocol: the program gets each ROI's points with
// the frame (intrinsics, index, ROI kind); its principal extents equal pca_box's.
TEST(External, ProtocolTwoOnSingleFramePerCaseAndPersistent) {
  const std::string yaml = R"(name: frames2
seed: 3
bunches:
  - preset: table-red
    count: 2
protocol: single_frame
sensor:
  type: d435
rig:
  type: robot_pass
  frames: 2
  spacing: 0.05
background:
  type: cloth
pipeline:
  rois: [manual_r, auto_r]
  view_filters:
    - type: pass_through
      min: [-1, -1000, 0.3]
      max: [1, 1000, 2.5]
estimators:
  - type: pca_box
)" + v2_entries("[height, length, width]", "convex_hull");
  const fs::path out = fresh_dir("external_v2_single_frame");
  run_scene_set(parse_scene_set(yaml, "frames2.yaml"), quiet(out, 2));
  const std::string csv = slurp(out / "results.csv");
  const EstimatorRows per_case = rows_of(csv, "v2_per_case"), persistent = rows_of(csv, "v2_persistent");
  expect_same_rows(per_case, persistent, 0, "persistent vs per case");
  expect_schema_ok(csv);
  expect_same_rows(extents_in_order(per_case), extents_in_order(rows_of(csv, "pca_box")), 1e-6, "numpy vs pca_box");
  bool manual = false;
  for (const auto& n : per_case.notes) {
    EXPECT_NE(n.find("grapebench-estimator-2, single_frame, frame "), std::string::npos) << n;
    manual = manual || n.find("manual_r, normals+viewpoints+colours") != std::string::npos;
  }
  EXPECT_TRUE(manual);
  print_timings(out, "single_frame");
}

// The stereo_pair protocol (seed 001): the built-in system and two external programs
// of the stereo request (the schema checker and the numpy baseline, per case and
// persistent) on the same pairs; every output kind is scored per pair.
TEST(External, StereoPairRequestAndPointAnswer) {
  const std::string source = GRAPEBENCH_SOURCE_DIR;
  std::string yaml = R"(name: pairs
seed: 4
protocol: stereo_pair
bunches:
  - preset: summer-black
    count: 2
sensor:
  type: stereo_rgb
  light: front
rig:
  type: stereo_stations
  distances: [0.6, 0.8]
estimators:
  - {type: luo2016_stereo, name: luo, berries: {radius_model: pinhole}}
)";
  for (const char* mode : {"per_case", "persistent"}) {
    const bool persistent = std::string(mode) == "persistent";
    const std::string flag = persistent ? ", --persistent" : "", keep = persistent ? "    persistent: true\n" : "";
    yaml += std::string("  - type: external\n    name: schema_") + mode + "\n    version: 2\n    input: stereo_pair\n" +
            keep + "    quantities: [hanging_height]\n" + "    command: [/usr/bin/python3, " + source +
            "/tests/bench/data/schema_check.py, " + source + "/docs/external-protocol.schema.json" + flag + "]\n";
    yaml += std::string("  - type: external\n    name: numpy_") + mode + "\n    version: 2\n    input: stereo_pair\n" +
            keep + "    quantities: [hanging_height]\n    command: [/usr/bin/python3, " + source +
            "/scripts/external/stereo_baseline.py" + flag + "]\n";
  }
  const fs::path out = fresh_dir("external_stereo_pair");
  run_scene_set(parse_scene_set(yaml, "pairs.yaml"), quiet(out, 2));
  const std::string csv = slurp(out / "results.csv");
  // The checker answers no point, so only its scalar rows are finite.
  for (const char* name : {"schema_per_case", "schema_persistent"}) {
    const EstimatorRows rows = rows_of(csv, name);
    ASSERT_FALSE(rows.notes.empty()) << name;
    for (const auto& n : rows.notes)
      EXPECT_NE(n.find("schema ok: grapebench-estimator-2 stereo_pair"), std::string::npos) << n;
    for (const auto& [key, v] : rows.estimate) {
      if (key.ends_with("/hanging_height")) {
        EXPECT_FALSE(std::isnan(v)) << name << " " << key;
      }
    }
  }
  const EstimatorRows per_case = rows_of(csv, "numpy_per_case"), persistent = rows_of(csv, "numpy_persistent");
  expect_same_rows(per_case, persistent, 0, "persistent vs per case");
  // Every pair gives each output kind's rows: 2 bunches x 2 stations.
  for (const char* q : {"cut_success", "cut_z", "cut_x", "cut_axis_distance", "hanging_height", "berries_found"}) {
    int n = 0;
    for (const auto& [key, v] : per_case.estimate)
      n += key.size() > std::strlen(q) && key.ends_with(std::string("/") + q);
    EXPECT_EQ(n, 4) << q;
  }
  // The baseline's cutting point is a point answer scored like the built-in's: its
  // distance from the stalk's axis is finite wherever it answered.
  int answered = 0;
  for (const auto& [key, v] : per_case.estimate) answered += key.ends_with("/cut_axis_distance") && std::isfinite(v);
  EXPECT_EQ(answered, 4) << csv;
  const EstimatorRows luo = rows_of(csv, "luo");
  double successes = 0;
  for (const auto& [key, v] : luo.estimate) successes += key.ends_with("/cut_success") ? v : 0;
  EXPECT_GT(successes, 0) << csv;
  print_timings(out, "stereo_pair");
}

// The stereo_pair protocol gives the same results at any thread count (OpenCV's own
// parallel loops included).
TEST(Run, StereoPairResultsDoNotDependOnThreads) {
  const std::string yaml = R"(name: pairs_threads
seed: 8
protocol: stereo_pair
bunches:
  - preset: table-red
    count: 2
sensor:
  type: stereo_rgb
  light: overcast
foliage: {}
rig:
  type: stereo_stations
  distances: [0.5, 0.9]
estimators:
  - {type: luo2016_stereo, segmentation: {component: cr}}
)";
  const SceneSet set = parse_scene_set(yaml, "pairs_threads.yaml");
  const fs::path a = fresh_dir("stereo_threads_1"), b = fresh_dir("stereo_threads_2");
  run_scene_set(set, quiet(a, 1));
  run_scene_set(set, quiet(b, 2));
  EXPECT_EQ(slurp(a / "results.csv"), slurp(b / "results.csv"));
  EXPECT_EQ(slurp(a / "summary.json"), slurp(b / "summary.json"));
  // Run again: both cases are reused (their failed rows' NaN estimates read back).
  bool null_estimate = false;
  for (const auto& e : fs::directory_iterator(a / "cases"))
    if (e.path().extension() == ".json") null_estimate |= slurp(e.path()).find("\"estimate\": null") != std::string::npos;
  ASSERT_TRUE(null_estimate) << "no failed row with a NaN estimate to read back";
  const RunOutcome again = run_scene_set(set, quiet(a, 2));
  EXPECT_EQ(again.reused, 2);
  EXPECT_EQ(slurp(a / "results.csv"), slurp(b / "results.csv"));
}

// A sweep over the `ray` renderer's light renders each pair once for all the lights
// (bench/runner.cpp's groups, StereoRgb::capture_together): every row the same as when
// each light's scene runs alone, and the cases of one bunch share one capture time
// (the sign they ran as a group).
TEST(Run, ALightSweepOnTheRayRendererScoresAsEachLightAlone) {
  const std::string head = R"(seed: 8
protocol: stereo_pair
bunches:
  - preset: table-red
    count: 1
sensor: {type: stereo_rgb, renderer: ray, width: 200, height: 150, pixel_pitch_um: 24, camera: {samples: 2}, light: )";
  const std::string tail = R"(}
rig:
  type: stereo_stations
  distances: [0.6]
estimators:
  - {type: luo2016_stereo, segmentation: {component: cr}}
)";
  const fs::path swept = fresh_dir("light_sweep");
  run_scene_set(parse_scene_set("name: light_sweep\n" + head + "front" + tail + "sweep:\n  sensor.light: [front, overcast]\n",
                                "light_sweep.yaml"),
                quiet(swept, 2));
  // The rows from `bunch` on, of lines whose first fields (scene, condition and, swept,
  // the light) are skipped, the swept ones of `light` alone.
  const auto rows = [](const std::string& csv, int skip, const std::string& light) {
    std::vector<std::string> out;
    std::istringstream in(csv);
    std::string line;
    std::getline(in, line);  // the header
    while (std::getline(in, line)) {
      std::size_t at = 0;
      std::string third;
      for (int k = 0; k < skip; ++k) {
        const std::size_t next = line.find(',', at);
        if (k == 2) third = line.substr(at, next - at);
        at = next + 1;
      }
      if (light.empty() || third == light) out.push_back(line.substr(at));
    }
    return out;
  };
  const std::string all = slurp(swept / "results.csv");
  for (const std::string light : {"front", "overcast"}) {
    const fs::path alone = fresh_dir("light_alone_" + light);
    run_scene_set(parse_scene_set("name: light_alone\n" + head + light + tail, "light_alone.yaml"), quiet(alone, 1));
    const std::vector<std::string> mine = rows(all, 3, light);
    EXPECT_FALSE(mine.empty()) << light;
    EXPECT_EQ(mine, rows(slurp(alone / "results.csv"), 2, "")) << light;
  }
  // timings.csv: scene, condition, bunch, estimator, seconds, peak_heap_mb, scan_seconds.
  std::map<std::string, std::set<std::string>> scan_seconds;  // bunch -> its cases' scan_seconds
  std::istringstream in(slurp(swept / "timings.csv"));
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::istringstream fields(line);
    for (std::string x; std::getline(fields, x, ',');) f.push_back(x);
    ASSERT_GE(f.size(), 7u) << line;
    scan_seconds[f[2]].insert(f[6]);
  }
  ASSERT_EQ(scan_seconds.size(), 1u);
  for (const auto& [bunch, seconds] : scan_seconds) EXPECT_EQ(seconds.size(), 1u) << "bunch " << bunch;
}

// A small seed 004 row section (2 vines, 1 bunch each), ideal pass; estimators follow.
std::string small_row_scene(const std::string& name, int count) {
  return "name: " + name + "\nseed: 9\nprotocol: classification\nbunches:\n  - preset: green-table\n    count: " +
         std::to_string(count) + R"(
vine_row: {vines: 2, vine_spacing: 0.5, bunches_per_vine: 1}
foliage: {leaves: 60, row_half_length: 0.5, occlusion: 0}
sensor: {type: ideal, width: 240, height: 180, hfov_deg: 60}
rig: {type: robot_pass, frames: 5, spacing: 0.15, distance: 0.8}
pipeline: {split_gap: 0.2, fusion: {voxel: 0.006}}
estimators:
)";
}

// Seed 004's classification protocol: a small row section, equal files at 1 and 2
// threads (feature extraction, SVM prediction and the reconstruction run in parallel).
TEST(Run, ClassificationResultsDoNotDependOnThreads) {
  const std::string yaml = small_row_scene("rows_threads", 2) + R"(  - {name: svm, type: dey2012_classification, train_per_class: 150, features: {radius: 0.03}, smoothing: {radius: 0.03}}
  - {name: gmm, type: dey2012_classification, train_per_class: 150, classifier: gmm, crf: false}
)";
  const SceneSet set = parse_scene_set(yaml, "rows_threads.yaml");
  const fs::path a = fresh_dir("rows_threads_1"), b = fresh_dir("rows_threads_2");
  run_scene_set(set, quiet(a, 1));
  run_scene_set(set, quiet(b, 2));
  const std::string results = slurp(a / "results.csv");
  EXPECT_EQ(results, slurp(b / "results.csv"));
  EXPECT_EQ(slurp(a / "summary.json"), slurp(b / "summary.json"));
  EXPECT_NE(results.find("auc_berry"), std::string::npos);
  const nlohmann::json summary = nlohmann::json::parse(slurp(a / "summary.json"));
  ASSERT_TRUE(summary.contains("classification"));
  for (const auto& cell : summary["classification"]) EXPECT_EQ(cell["cases"], 2) << cell.dump();  // every row ok
}

// The real photogrammetry path: rendered colour pairs, SGBM, fusion; its disparity
// error is measured against the exact depths of the pixels it matched.
TEST(Run, ClassificationFromRenderedPairsMeasuresItsDisparityError) {
  const std::string yaml = R"(name: rows_sgbm
seed: 10
protocol: classification
bunches:
  - preset: green-table
vine_row: {vines: 1, bunches_per_vine: 2}
foliage: {leaves: 40, row_half_length: 0.35, occlusion: 0}
sensor: {type: stereo_rgb, width: 320, height: 240, focal_length_mm: 3, background: plain, light: overcast}
rig: {type: robot_pass, frames: 4, spacing: 0.12, distance: 0.8}
pipeline: {reconstruction: sgbm, sgbm: {min_depth: 0.5, max_depth: 1.6}, split_gap: 0.1}
estimators:
  - {name: rgb, type: dey2012_classification, train_per_class: 100, features: {scales: 0}, crf: false}
)";
  const fs::path a = fresh_dir("rows_sgbm");
  run_scene_set(parse_scene_set(yaml, "rows_sgbm.yaml"), quiet(a, 2));
  const nlohmann::json summary = nlohmann::json::parse(slurp(a / "summary.json"));
  ASSERT_EQ(summary["reconstruction"].size(), 1u) << summary.dump();
  const double sd = summary["reconstruction"][0]["disparity_error_px"];
  EXPECT_GT(sd, 0.05);
  EXPECT_LT(sd, 3.0);
  EXPECT_GT(summary["reconstruction"][0]["points"].get<int>(), 1000);
  for (const auto& cell : summary["classification"]) EXPECT_EQ(cell["cases"], 1) << cell.dump();
  // The error's structure: correlated between neighbours, less so further apart; the
  // pixels behind edges partly fattened; every class partly matched.
  const auto& rec = summary["reconstruction"][0];
  const auto r = rec["disparity_error_correlation_1_2_4_8px"].get<std::vector<double>>();
  ASSERT_EQ(r.size(), 4u);
  EXPECT_GT(r[0], 0.3);
  EXPECT_LE(r[0], 1.0);
  EXPECT_GT(r[0], r[3]);
  EXPECT_GE(rec["disparity_fattening"].get<double>(), 0.0);
  EXPECT_LT(rec["disparity_fattening"].get<double>(), 1.0);
  for (const char* cls : {"berry", "branch", "leaf"}) {
    EXPECT_GT(rec["matched_fraction"][cls].get<double>(), 0.05) << cls;
    EXPECT_LE(rec["matched_fraction"][cls].get<double>(), 1.0) << cls;
    EXPECT_LT(std::abs(rec["disparity_bias"][cls].get<double>()), 1.0) << cls;
  }
  // The left images' pixel noise per class: OpenGL's noise of sd 2 DN read back about
  // the 3 x 3 median (2.0 on the flat leaves and stems, 2.4-2.9 on the shaded berries).
  for (const char* cls : {"berry", "branch", "leaf"}) {
    const auto spread = rec["pixel_noise_dn"][cls].get<std::vector<double>>();
    ASSERT_EQ(spread.size(), 3u) << cls;
    for (const double v : spread) EXPECT_GT(v, 1.5) << cls;
    for (const double v : spread) EXPECT_LT(v, 3.5) << cls;
  }
  // Sub-pixel disparities drawn toward whole pixels, as on the rendered slanted plane.
  EXPECT_GT(rec["disparity_locking"].get<double>(), 0.03);
  EXPECT_LT(rec["disparity_locking"].get<double>(), 0.3);
  // The case file keeps them and reads back.
  const nlohmann::json c = nlohmann::json::parse(slurp(a / "cases" / "c0000_b0000.json"));
  EXPECT_EQ(c["disparity_error_correlation"].size(), 4u);
  EXPECT_EQ(c["matched_fraction"].size(), 3u);
  EXPECT_EQ(c["disparity_bias"].size(), 3u);
  EXPECT_EQ(c["pixel_noise_dn"].size(), 9u);
  EXPECT_DOUBLE_EQ(c["disparity_locking"].get<double>(), rec["disparity_locking"].get<double>());
}

// Seed 004 through the external protocol: a classification request (coloured PLY,
// classes, training labels) checked against the schema, and per-point score answers
// from the Python example, per case and persistent alike.
TEST(External, ClassificationRequestAndScoreAnswer) {
  const std::string source = GRAPEBENCH_SOURCE_DIR;
  std::string yaml = small_row_scene("rows_external", 1);
  yaml += "  - {name: schema, type: external, version: 2, input: labelled_cloud, command: [/usr/bin/python3, " + source +
          "/tests/bench/data/schema_check.py, " + source + "/docs/external-protocol.schema.json]}\n";
  for (const char* mode : {"per_case", "persistent"}) {
    yaml += std::string("  - {name: colour_") + mode + ", type: external, version: 2, input: labelled_cloud" +
            (std::string(mode) == "persistent" ? ", persistent: true" : "") + ", command: [/usr/bin/python3, " + source +
            "/scripts/external/colour_classifier.py" + (std::string(mode) == "persistent" ? ", --persistent" : "") +
            "]}\n";
  }
  const fs::path out = fresh_dir("external_classification");
  run_scene_set(parse_scene_set(yaml, "rows_external.yaml"), quiet(out, 2));
  const std::string csv = slurp(out / "results.csv");
  const EstimatorRows schema = rows_of(csv, "schema");
  ASSERT_FALSE(schema.notes.empty()) << csv;
  for (const auto& n : schema.notes)
    EXPECT_NE(n.find("schema ok: grapebench-estimator-2 classification"), std::string::npos) << n;
  // Equal scores: every AUC is one half.
  for (const auto& [key, v] : schema.estimate) {
    if (key.ends_with("/auc_berry")) {
      EXPECT_DOUBLE_EQ(v, 0.5) << key;
    }
  }
  const EstimatorRows per_case = rows_of(csv, "colour_per_case"), persistent = rows_of(csv, "colour_persistent");
  expect_same_rows(per_case, persistent, 0, "persistent vs per case");
  int aucs = 0;
  for (const auto& [key, v] : per_case.estimate) {
    if (!key.ends_with("/auc_berry")) continue;
    ++aucs;
    EXPECT_GT(v, 0.7) << key;  // colour separates the classes well in this row
  }
  EXPECT_EQ(aucs, 1);
}

// Perturbed poses: the back-projection uses each view's pose moved by the scene's pose
// errors; the case records their size, and a shape-only classifier suffers.
TEST(Run, ClassificationWithPerturbedPoses) {
  std::string yaml = small_row_scene("rows_poses", 1) +
                     "  - {name: s2, type: dey2012_classification, train_per_class: 150, features: {radius: 0.03, "
                     "colour: false}, crf: false}\n";
  const SceneSet exact = parse_scene_set(yaml, "exact.yaml");
  const std::string at = "pipeline: {split_gap: 0.2,";
  yaml.replace(yaml.find(at), at.size(), "pipeline: {pose_rotation_sd: 2, pose_translation_sd: 0.01, split_gap: 0.2,");
  const SceneSet moved = parse_scene_set(yaml, "moved.yaml");
  const fs::path a = fresh_dir("rows_exact_poses"), b = fresh_dir("rows_moved_poses");
  run_scene_set(exact, quiet(a, 2));
  run_scene_set(moved, quiet(b, 2));
  const std::string ca = slurp(a / "results.csv"), cb = slurp(b / "results.csv");
  const EstimatorRows ra = rows_of(ca, "s2"), rb = rows_of(cb, "s2");
  double auc_a = NAN, auc_b = NAN;
  for (const auto& [key, v] : ra.estimate) {
    if (key.ends_with("/auc_berry")) auc_a = v;
  }
  for (const auto& [key, v] : rb.estimate) {
    if (key.ends_with("/auc_berry")) auc_b = v;
  }
  EXPECT_LT(auc_b, auc_a);  // views no longer agree: smeared shapes
  EXPECT_NE(cb.find("rotation_error_max_deg"), std::string::npos);
  const nlohmann::json one = nlohmann::json::parse(slurp(b / "cases" / "c0000_b0000.json"));
  EXPECT_GT(one["rotation_error_mean_deg"].get<double>(), 0.5);
  EXPECT_GT(one["translation_error_mean_mm"].get<double>(), 5);
}

// COLMAP's SfM as the pose source: rendered textured leaves, every view placed, its
// poses (after the similarity fit) within a degree and a centimetre of the truth; the
// results repeat exactly at another thread count (without the seed shim, COLMAP's
// matches differed between runs).
TEST(Run, ClassificationWithColmapPoses) {
  const std::string yaml = R"(name: rows_colmap
seed: 11
protocol: classification
bunches:
  - preset: green-table
vine_row: {vines: 1, bunches_per_vine: 2}
foliage: {leaves: 60, row_half_length: 0.4, occlusion: 0}
sensor: {type: stereo_rgb, width: 400, height: 300, focal_length_mm: 4, background: plain, light: overcast,
         leaf_texture: 0.4}
rig: {type: robot_pass, frames: 6, spacing: 0.1, distance: 0.8}
pipeline: {reconstruction: sgbm, poses: colmap, sgbm: {min_depth: 0.5, max_depth: 1.6}, split_gap: 0.1}
estimators:
  - {name: rgb, type: dey2012_classification, train_per_class: 100, features: {scales: 0}, crf: false}
)";
  const fs::path out = fresh_dir("rows_colmap");
  run_scene_set(parse_scene_set(yaml, "rows_colmap.yaml"), quiet(out, 2));
  const nlohmann::json c = nlohmann::json::parse(slurp(out / "cases" / "c0000_b0000.json"));
  ASSERT_TRUE(c["ok"].get<bool>()) << c["error"];
  EXPECT_EQ(c["views_registered"], 6);
  EXPECT_LT(c["rotation_error_max_deg"].get<double>(), 1.0);
  EXPECT_LT(c["translation_error_max_mm"].get<double>(), 10.0);
  const fs::path again = fresh_dir("rows_colmap_again");
  run_scene_set(parse_scene_set(yaml, "rows_colmap.yaml"), quiet(again, 1));
  EXPECT_EQ(slurp(again / "results.csv"), slurp(out / "results.csv"));
  EXPECT_EQ(slurp(again / "summary.json"), slurp(out / "summary.json"));
  const nlohmann::json c1 = nlohmann::json::parse(slurp(again / "cases" / "c0000_b0000.json"));
  for (const char* key : {"rotation_error_mean_deg", "translation_error_mean_mm", "points", "roc"})
    EXPECT_EQ(c1[key], c[key]) << key;
}

TEST(Run, ClassificationNeedsItsRowAndLabelledCloudEstimators) {
  const std::string base = "name: x\nseed: 1\nbunches: [{preset: green-table}]\nsensor: {type: ideal}\n"
                           "rig: {type: robot_pass}\n";
  EXPECT_THROW(parse_scene_set(base + "protocol: classification\n", "a.yaml"), InputError);
  EXPECT_THROW(parse_scene_set(base + "vine_row: {}\n", "b.yaml"), InputError);
  EXPECT_THROW(parse_scene_set(base + "protocol: classification\nvine_row: {}\nestimators: [{type: convex_hull}]\n",
                               "c.yaml"),
               InputError);
  EXPECT_THROW(parse_scene_set(base + "estimators: [{type: dey2012_classification}]\n", "d.yaml"), InputError);
  EXPECT_NO_THROW(parse_scene_set(
      base + "protocol: classification\nvine_row: {}\nestimators: [{type: dey2012_classification}]\n", "e.yaml"));
}

// Seed 003's single-frame pipeline: rows per frame and ROI kind, the perfect manual
// ROI exactly on the bunch, Err (Eq. 3) recomputed from the rows, a named sweep axis.
TEST(Run, SingleFramePipelineGivesTableTwoFromItsRows) {
  const std::string scene = R"(name: frames
seed: 3
bunches:
  - preset: table-red
    count: 2
protocol: single_frame
sensor:
  type: d435
rig:
  type: robot_pass
  frames: 2
  spacing: 0.1
  distance: 1.5
background:
  type: cloth
  distance: 0.4
  colour: [0.03, 0.03, 0.03]
foliage:
  leaves: 20
pipeline:
  fine_tune: false
  view_filters:
    - type: pass_through
      min: [-1, -1000, 0.3]
      max: [1, 1000, 2.5]
estimators:
  - {type: percentile_box_edges, name: G_E}
sweep:
  background.type: [none, cloth]
)";
  const fs::path out = fresh_dir("frames");
  const SceneSet set = parse_scene_set(scene, "frames.yaml");
  ASSERT_EQ(set.conditions.size(), 2u);
  EXPECT_EQ(set.conditions[1].label, "type=cloth");
  const RunOutcome r = run_scene_set(set, quiet(out));
  ASSERT_TRUE(r.complete);
  // Recompute Err of manual_r from results.csv and compare with size_error.csv.
  std::istringstream csv(slurp(out / "results.csv"));
  std::string line;
  std::getline(csv, line);
  std::map<std::string, double> half_err;  // frame key -> sum of 0.5 |e - t|
  int manual_rows = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::stringstream ls(line);
    for (std::string x; std::getline(ls, x, ',');) f.push_back(x);
    // scene,condition,type,bunch,preset,seed,estimator,type,quantity,unit,estimate,truth,error,rel,ok,wt,points,
    // rot,trans,message,frame,roi,region,region_points,region_precision
    ASSERT_EQ(f.size(), 25u) << line;
    if (f[21] != "manual_r" || f[1] != "type=cloth" || f[8] == "volume") continue;
    ++manual_rows;
    EXPECT_EQ(f[24], "1") << "the perfect manual ROI holds only bunch points: " << line;
    half_err[f[3] + "/" + f[20]] += 0.5 * std::abs(std::stod(f[12])) / 1e3;  // mm -> m
  }
  EXPECT_EQ(manual_rows, 2 * 2 * 2);  // bunches x frames x (major, minor)
  double sum = 0;
  for (const auto& [k, e] : half_err) sum += e;
  const std::string table = slurp(out / "size_error.csv");
  std::istringstream t(table);
  std::getline(t, line);
  bool found = false;
  while (std::getline(t, line)) {
    if (line.rfind("\"type=cloth\",G_E,manual_r,", 0) != 0) continue;
    std::vector<std::string> f;
    std::stringstream ls(line);
    for (std::string x; std::getline(ls, x, ',');) f.push_back(x);
    EXPECT_EQ(f[3], "4");
    EXPECT_NEAR(std::stod(f[5]), 100 * sum / 4, 1e-3);  // cm
    found = true;
  }
  EXPECT_TRUE(found) << table;
  EXPECT_NE(slurp(out / "report.html").find("seed 003 Table II"), std::string::npos);
  EXPECT_FALSE(slurp(out / "size_error_table.md").empty());
}

}  // namespace
}  // namespace grapebench
