#include "bench/scene_file.h"
#include "file_text.h"
#include "scratch.h"
#include "scene_error.h"
#include "bench/synth_run.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

namespace grapebench {
namespace {

std::string error_of(const std::string& yaml) {
  try {
    parse_scene(yaml, "scene.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Scene, ParsesPresetsOverridesAndDerivesSeeds) {
  const Scene s = parse_scene(
      "seed: 9\nbunches:\n  - preset: wine-red\n    count: 2\n    compactness: 0.3\n  - preset: table-red\n", "s.yaml");
  ASSERT_EQ(s.groups.size(), 2u);
  EXPECT_DOUBLE_EQ(s.groups[0].params.compactness, 0.3);
  const auto jobs = bunch_jobs(s);
  ASSERT_EQ(jobs.size(), 3u);
  EXPECT_NE(jobs[0].seed, jobs[1].seed);
  EXPECT_EQ(jobs[2].preset, "table-red");
}

TEST(Scene, EveryKindOfErrorNamesFileLineAndKey) {
  // Out of range.
  auto m = error_of("seed: 1\nbunches:\n  - preset: table-red\n    compactness: 1.5\n");
  EXPECT_NE(m.find("scene.yaml:4"), std::string::npos) << m;
  EXPECT_NE(m.find("bunches[0].compactness"), std::string::npos) << m;
  EXPECT_NE(m.find("[0, 1]"), std::string::npos) << m;
  // Unknown key.
  m = error_of("seed: 1\nbunches:\n  - preset: table-red\n    berry_size: 3\n");
  EXPECT_NE(m.find("scene.yaml:4: unknown key 'bunches[0].berry_size'"), std::string::npos) << m;
  // Unknown preset.
  m = error_of("seed: 1\nbunches:\n  - preset: concord\n");
  EXPECT_NE(m.find("scene.yaml:3"), std::string::npos) << m;
  EXPECT_NE(m.find("allowed: table-red"), std::string::npos) << m;
  // Missing seed, wrong type, cross-field rule.
  EXPECT_NE(error_of("bunches:\n  - preset: table-red\n").find("'seed'"), std::string::npos);
  EXPECT_NE(error_of("seed: -4\nbunches:\n  - preset: table-red\n").find("unsigned"), std::string::npos);
  m = error_of("seed: 1\nbunches:\n  - preset: table-red\n    berry_count_min: 50\n    berry_count_max: 20\n");
  EXPECT_NE(m.find("berry_count_min must not exceed"), std::string::npos) << m;
  EXPECT_NE(m.find("scene.yaml:"), std::string::npos) << m;
}

// Issue 23's reproducers: yaml-cpp accepted these silently (the first duplicate won,
// `!!str 5` was read as 5, a second document and a `name` holding a path were taken).
TEST(Scene, StrictYamlAndSafeNames) {
  const struct {
    std::string yaml, message;
  } cases[] = {
      {"seed: 5\nseed: 999\nbunches:\n  - preset: table-red\n", "scene.yaml:2: 'seed' is given twice"},
      {"seed: 5\nbunches:\n  - preset: table-red\n    count: 1\n    count: 2\n", "scene.yaml:5: 'count' is given twice"},
      {"seed: !!str 5\nbunches:\n  - preset: table-red\n", "scene.yaml:1: explicit YAML tag"},
      {"seed: 5\nbunches:\n  - preset: table-red\n---\nseed: 6\n", "scene.yaml:4: a second YAML document"},
      // Found by tests/fuzz/scene_fuzz.cpp: a stray comma made yaml-cpp's LoadAll loop
      // forever, allocating (a scene file of 1 KB took the machine's memory).
      {",\nseed: 5\nbunches:\n  - preset: table-red\n", "scene.yaml:1: a second YAML document, or text after the first"},
      {"seed: 5\n? [a, b]\n: 3\nbunches:\n  - preset: table-red\n", "scene.yaml:2: a key must be a plain name"},
      {"name: ../../x\nseed: 5\nbunches:\n  - preset: table-red\n", "'../../x' is not a safe folder name"},
      {"name: /tmp/x\nseed: 5\nbunches:\n  - preset: table-red\n", "'/tmp/x' is not a safe folder name"},
      {"name: a b\nseed: 5\nbunches:\n  - preset: table-red\n", "'a b' is not a safe folder name"},
      {"name: " + std::string(101, 'a') + "\nseed: 5\nbunches:\n  - preset: table-red\n", "is not a safe folder name"},
      // Issue 39: a Latin-1 comment or a UTF-16 file ran every case and then exited 3
      // writing the manifest; a billion-laughs document (aliases of aliases) ran for
      // minutes. Both refused at once.
      {"seed: 5\nbunches:\n  - preset: table-red\n# caf\xE9\n", "scene.yaml:4: not UTF-8 (byte 44, 0xE9)"},
      {std::string("\xFF\xFEs\0e\0", 6), "scene.yaml:1: not UTF-8 (byte 0, 0xFF)"},
      {"l0: &a [x, x, x, x, x, x, x, x, x]\nl1: &b [*a, *a, *a, *a, *a, *a, *a, *a, *a]\n"
       "l2: [*b, *b, *b, *b, *b, *b, *b, *b, *b]\nseed: 5\nbunches:\n  - preset: table-red\n",
       "scene.yaml:2: a YAML alias (*name): not supported"},
      {"seed: 5\nbunches:\n  - &p {preset: table-red}\n  - *p\n", "scene.yaml:4: a YAML alias"},
      {"seed: 5\nbunches:\n  - {preset: table-red, count: 100000}\n  - {preset: table-red, count: 100000}\n"
       "sweep:\n  seed: [1, 2, 3, 4, 5, 6]\n", "the scene expands to 1200000 cases (6 sweep points x 200000 bunches); at most 1000000"},
      {"name: \"a\\0b\"\nseed: 5\nbunches:\n  - preset: table-red\n", "'a\\x00b' is not a safe folder name"},
  };
  for (const auto& c : cases) {
    const std::string error = scene_error(c.yaml);
    EXPECT_NE(error.find(c.message), std::string::npos) << c.yaml << "\n-> " << error;
  }
  EXPECT_EQ(scene_error("name: seed004_green-2.b\nseed: 5\nbunches:\n  - preset: table-red\n"), "");
}

// Protocol detection: its keys, its sensor and its estimators' input are checked when
// the scene is read.
TEST(Scene, DetectionProtocolKeysSensorAndEstimatorsAreChecked) {
  const std::string head = "seed: 1\nprotocol: detection\nbunches:\n  - preset: wine-red\n";
  const std::string colour = "sensor: {type: stereo_rgb, width: 80, height: 64}\nrig: {type: stereo_stations}\n";
  auto m = error_of(head + colour + "pipeline: {categories: [bunch, grape]}\n");
  EXPECT_NE(m.find("pipeline.categories"), std::string::npos) << m;
  EXPECT_NE(m.find("bunch, berry, stalk, leaf, cane"), std::string::npos) << m;
  m = error_of(head + colour + "pipeline: {max_detections: 5}\n");
  EXPECT_NE(m.find("pipeline.max_detections"), std::string::npos) << m;
  EXPECT_NE(m.find("[10, 100000]"), std::string::npos) << m;
  m = error_of(head + "sensor: {type: kinect_v2}\nrig: {type: turntable}\n");
  EXPECT_NE(m.find("detection needs a colour camera"), std::string::npos) << m;
  m = error_of(head + colour + "estimators:\n  - type: convex_hull\n");
  EXPECT_NE(m.find("measures a cloud, and protocol detection gives an image"), std::string::npos) << m;
  // Keys of other protocols are refused.
  m = error_of(head + colour + "pipeline: {cut_tolerance: 2}\n");
  EXPECT_NE(m.find("cut_tolerance"), std::string::npos) << m;
  EXPECT_EQ(error_of(head + colour + "pipeline: {categories: [berry], min_pixels: 4, max_detections: 500}\n"
                                     "estimators:\n  - {type: luo2016_instances, regions: all, depth: 1}\n"),
            "");
}

TEST(Scene, SensorRigAndBackgroundSectionsAreStrict) {
  const Scene ok = parse_scene(
      "seed: 1\nbunches:\n  - preset: wine-red\nsensor:\n  type: d435\n  noise_scale: 2\nrig:\n  type: robot_pass\n"
      "  frames: 2\nbackground:\n  type: cloth\n",
      "s.yaml");
  ASSERT_TRUE(ok.sensor && ok.rig);
  EXPECT_EQ(ok.sensor->type(), "d435");
  EXPECT_EQ(ok.rig->type(), "robot_pass");
  EXPECT_EQ(ok.background.type, BackgroundType::Cloth);
  // Unknown sensor type names the allowed ones.
  auto m = error_of("seed: 1\nbunches:\n  - preset: wine-red\nsensor:\n  type: lidar\n");
  EXPECT_NE(m.find("scene.yaml:5"), std::string::npos) << m;
  EXPECT_NE(m.find("allowed: kinect_v2, d435, stereo_rgb, ideal"), std::string::npos) << m;
  // Out-of-range sensor parameter.
  m = error_of("seed: 1\nbunches:\n  - preset: wine-red\nsensor:\n  type: kinect_v2\n  noise_scale: -1\n");
  EXPECT_NE(m.find("scene.yaml:6"), std::string::npos) << m;
  EXPECT_NE(m.find("sensor.noise_scale"), std::string::npos) << m;
  EXPECT_NE(m.find("[0, 20]"), std::string::npos) << m;
  // Unknown rig key, bad boolean.
  m = error_of("seed: 1\nbunches:\n  - preset: wine-red\nsensor:\n  type: ideal\nrig:\n  type: turntable\n  vews: 3\n");
  EXPECT_NE(m.find("scene.yaml:8: unknown key 'rig.vews'"), std::string::npos) << m;
  m = error_of("seed: 1\nbunches:\n  - preset: wine-red\nsensor:\n  type: ideal\nrig:\n  bottom_view: maybe\n");
  EXPECT_NE(m.find("expected true or false"), std::string::npos) << m;
  // A rig without a sensor.
  m = error_of("seed: 1\nbunches:\n  - preset: wine-red\nrig:\n  type: turntable\n");
  EXPECT_NE(m.find("needs a `sensor:` section"), std::string::npos) << m;
}

// A key read only under one value of a swept setting (the `ray` renderer's camera in
// a sweep over the renderer, as seed001_renderers.yaml pins sky_stride) stands in the
// scene: the ray cells read it, the OpenGL cells leave it. Without that sweep it is
// still refused.
TEST(Scene, AKeyOfOneSweptRendererStandsInEveryCondition) {
  const std::string head = "seed: 1\nbunches:\n  - preset: wine-red\nrig: {type: stereo_stations}\n";
  const std::string sensor = "sensor:\n  type: stereo_rgb\n  width: 80\n  height: 64\n  light: front\n  camera: {sky_stride: 1}\n";
  const SceneSet set = parse_scene_set(head + sensor + "sweep:\n  sensor.renderer: [opengl, ray]\n", "scene.yaml");
  ASSERT_EQ(set.conditions.size(), 2u);
  const nlohmann::ordered_json opengl = set.conditions[0].scene.sensor->describe();
  const nlohmann::ordered_json ray = set.conditions[1].scene.sensor->describe();
  EXPECT_EQ(opengl["renderer"], "opengl");
  EXPECT_FALSE(opengl.contains("camera")) << opengl.dump();
  EXPECT_EQ(ray["camera"]["sky_stride"], 1) << ray.dump();  // not the default, 2
  // Out of range, it is named where a ray cell reads it.
  auto m = scene_error(head + "sensor:\n  type: stereo_rgb\n  light: front\n  camera: {sky_stride: 3}\nsweep:\n  sensor.renderer: [opengl, ray]\n");
  EXPECT_NE(m.find("sky_stride"), std::string::npos) << m;
  EXPECT_NE(m.find("[1, 2]"), std::string::npos) << m;
  // An unknown key in it is still named.
  m = scene_error(head + "sensor:\n  type: stereo_rgb\n  light: front\n  camera: {sky_strid: 1}\nsweep:\n  sensor.renderer: [opengl, ray]\n");
  EXPECT_NE(m.find("sky_strid"), std::string::npos) << m;
  // Without the sweep, or under a sweep of another key, OpenGL refuses it.
  for (const std::string& tail : {std::string(), std::string("sweep:\n  sensor.width: [80, 96]\n")}) {
    m = scene_error(head + sensor + tail);
    EXPECT_NE(m.find("'sensor.camera': is read only with renderer: ray or cycles"), std::string::npos) << m;
  }
  // A key no swept value reads (Cycles' settings in a sweep of OpenGL and ray) is an
  // error, as without the sweep, even misspelt inside.
  m = scene_error(head + "sensor:\n  type: stereo_rgb\n  light: front\n  cycles: {smaples: 1}\nsweep:\n"
                         "  sensor.renderer: [opengl, ray]\n");
  EXPECT_NE(m.find("scene.yaml:8: 'sensor.cycles': is read only with renderer: cycles; no value of the sweep selects it"),
            std::string::npos) << m;
  // `scan` and `synth` read the scene at its written values: the OpenGL scene, the
  // camera left; and refused where no cell reads it.
  const Scene nominal = parse_scene(head + sensor + "sweep:\n  sensor.renderer: [opengl, ray]\n", "scene.yaml");
  EXPECT_EQ(nominal.sensor->describe()["renderer"], "opengl");
  m = error_of(head + "sensor:\n  type: stereo_rgb\n  light: front\n  cycles: {samples: 4}\nsweep:\n"
                      "  sensor.renderer: [opengl, ray]\n");
  EXPECT_NE(m.find("no value of the sweep selects it"), std::string::npos) << m;
}

TEST(SynthRun, OutputsAreByteIdenticalAtAnyThreadCount) {
  const Scene s = parse_scene("seed: 5\nbunches:\n  - preset: wine-red\n    count: 3\n", "t.yaml");
  const auto base = scratch("threads_test");
  SynthOptions one, two;
  one.out = base / "one";
  one.threads = 1;
  two.out = base / "two";
  two.threads = 2;
  run_synth(bunch_jobs(s), one);
  run_synth(bunch_jobs(s), two);
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(one.out)) {
    // Not EXPECT_EQ: on a mismatch it prints both files (megabytes of binary PLY,
    // escaped: it once took 24 GB).
    EXPECT_TRUE(slurp(e.path()) == slurp(two.out / e.path().filename())) << e.path();
    ++files;
  }
  EXPECT_EQ(files, 3 * 3 + 2);  // json, ply, obj per bunch; parts.mtl; summary.csv
  for (const auto& e : std::filesystem::directory_iterator(one.out)) {
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << "leftover temporary file";
  }
  std::filesystem::remove_all(base);
}

// `synth --alpha-wrap`: the truth JSON's alpha_wrap block and summary.csv's column
// carry the same wrap, tighter than the hull and looser than the solid; off, the
// column is empty and the block absent.
TEST(SynthRun, TheAlphaWrapReachesTheJsonAndTheSummary) {
  const Scene s = parse_scene("seed: 5\nbunches:\n  - preset: wine-red\n    count: 1\n", "t.yaml");
  const auto base = scratch("alpha_wrap_test");
  SynthOptions o;
  o.out = base;
  o.write_mesh = false;
  o.alpha_wrap = 0.01;
  const auto results = run_synth(bunch_jobs(s), o);
  const GroundTruth& g = results.at(0).truth;
  ASSERT_GT(g.alpha_wrap_volume, g.volume.solid);
  EXPECT_LT(g.alpha_wrap_volume, g.envelope_volume);
  const auto json = nlohmann::json::parse(slurp(base / "bunch_0000.json"));
  EXPECT_EQ(json["alpha_wrap"]["alpha_m"].get<double>(), 0.01);
  EXPECT_NEAR(json["alpha_wrap"]["volume_m3"].get<double>(), g.alpha_wrap_volume, 1e-15);
  const std::string csv = slurp(base / "summary.csv");
  const std::string last = csv.substr(csv.rfind(',', csv.size() - 2) + 1);
  EXPECT_NEAR(std::stod(last), g.alpha_wrap_volume * 1e6, 1e-6 * g.alpha_wrap_volume * 1e6) << csv;
  o.alpha_wrap = 0;
  run_synth(bunch_jobs(s), o);
  EXPECT_FALSE(nlohmann::json::parse(slurp(base / "bunch_0000.json")).contains("alpha_wrap"));
  const std::string off = slurp(base / "summary.csv");
  EXPECT_EQ(off.substr(off.size() - 2), ",\n") << off;
  std::filesystem::remove_all(base);
}

}  // namespace
}  // namespace grapebench
