// Every key table and registry the scene reader uses: each key in the generated
// --help with its default in range; a manifest's scene reads back as the same scene;
// an unknown key, or one the chosen type or method does not read, fails with file:line
// for every kind.
#include "algorithms/external/python_estimator.h"
#include "bench/scene_file.h"
#include "scene_error.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

namespace grapebench {
namespace {

namespace fs = std::filesystem;

std::string help_of(const std::string& subcommand) {
  const std::string cmd = std::string(GRAPEBENCH_EXE) + " " + subcommand + " --help 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  std::string out;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), buf.size(), pipe.get())) out += buf.data();
  return out;
}

// Every table a scene can set, by the section it is written in.
struct Table {
  std::string where;  // "sensor: kinect_v2", "pipeline", ...
  std::string help;   // the subcommand whose --help documents it
  std::vector<KeyInfo> keys;
};

template <class Product>
void add_registry(std::vector<Table>& out, const Registry<Product>& r, const std::string& help) {
  for (const auto& e : r.entries()) out.push_back({r.kind() + ": " + e.type, help, e.keys()});
}

std::vector<Table> all_tables() {
  std::vector<Table> t;
  t.push_back({"bunches", "synth", bunch_param_table().keys(BunchParams{})});
  add_registry(t, sensor_registry(), "scan");
  add_registry(t, rig_registry(), "scan");
  t.push_back({"background", "scan", background_param_table().keys(BackgroundSpec{})});
  t.push_back({"foliage", "scan", foliage_param_table().keys(FoliageParams{})});
  t.push_back({"pipeline", "run", pipeline_param_table().keys(PipelineSpec{})});
  add_registry(t, filter_registry(), "run");
  add_registry(t, registration_registry(), "run");
  add_registry(t, estimator_registry(), "run");
  return t;
}

TEST(KeyTables, EveryKeyIsInTheGeneratedHelpWithItsDefaultInRange) {
  std::map<std::string, std::string> help;
  int keys = 0;
  for (const auto& table : all_tables()) {
    if (!help.count(table.help)) help[table.help] = help_of(table.help);
    const std::string& h = help[table.help];
    for (const auto& k : table.keys) {
      ++keys;
      EXPECT_TRUE(k.default_in_range) << table.where << "." << k.key << " = " << k.default_value << " not in "
                                      << k.range;
      EXPECT_FALSE(k.doc.empty()) << table.where << "." << k.key;
      // The key starts a help row, followed by its unit.
      const auto at = h.find(" " + k.key + " ");
      ASSERT_NE(at, std::string::npos) << table.where << "." << k.key << " missing from " << table.help << " --help";
      EXPECT_NE(h.find(k.doc), std::string::npos) << table.where << "." << k.key;
    }
    if (table.where.rfind("sensor: ", 0) == 0 || table.where.rfind("estimator: ", 0) == 0) {
      EXPECT_NE(h.find(table.where.substr(table.where.find(' ') + 1) + ": "), std::string::npos) << table.where;
    }
  }
  EXPECT_GT(keys, 150);
}

// A scene that sets many keys away from their defaults, across every section.
const char* kBusyScene = R"(name: busy
seed: 77
bunches:
  - preset: wine-red
    count: 2
    compactness: 0.9
    berry_colour: [0.2, 0.1, 0.3]
  - preset: green-table
sensor:
  type: kinect_v2
  noise_scale: 2
  edge_filter: false
rig:
  type: turntable
  views: 8
  step_deg: 45
  bottom_view: true
  bottom_distance: 0.5
background:
  type: plate
  colour: [0.1, 0.2, 0.3]
foliage:
  leaves: 12
pipeline:
  segmentation: none
  registration:
    type: known_angle_icp
    bottom_band: 0.02
    icp:
      max_iterations: 20
      point_to_plane: true
  view_filters:
    - type: pass_through
      min: [-1, -1, 0.2]
      max: [1, 1, 2]
    - type: region_growing
      smoothness_deg: 5
  cloud_filters:
    - type: statistical_outlier
      mean_k: 20
    - type: lccp_stalk_removal
estimators:
  - type: poisson
    name: PB_screened
    solver: screened
    curved: true
    orient: facing
  - type: section_perimeters
    outline: angular
    angular_bins: 90
  - type: ellipsoid_fit
    measure: diameters
  - type: external
    command: [python3, "{scene_dir}/x.py", --flag]
    quantities: [volume, height]
    timeout: 12
)";

void expect_reads_back(const Scene& scene, const std::string& what) {
  const nlohmann::ordered_json j = scene_json(scene);
  Scene back;
  try {
    back = parse_scene(j.dump(1), "manifest of " + what);
  } catch (const InputError& e) {
    FAIL() << what << ": the manifest's scene does not read back: " << e.what() << "\n" << j.dump(1);
  }
  EXPECT_EQ(scene_json(back).dump(1), j.dump(1)) << what;
}

TEST(KeyTables, AManifestsSceneReadsBackAsTheSameScene) {
  expect_reads_back(parse_scene(kBusyScene, "busy.yaml"), "the busy scene");
  const nlohmann::ordered_json busy = scene_json(parse_scene(kBusyScene, "busy.yaml"));
  EXPECT_EQ(busy["pipeline"]["registration"]["icp"]["max_iterations"].get<int>(), 20);
  EXPECT_EQ(busy["estimators"][1]["angular_bins"].get<int>(), 90);
  EXPECT_FALSE(busy["pipeline"]["registration"].contains("group_size"));  // not a key of known_angle_icp
  int scenes = 0;
  for (const auto& f : fs::directory_iterator(fs::path(GRAPEBENCH_SOURCE_DIR) / "scenes")) {
    if (f.path().extension() != ".yaml") continue;
    const SceneSet set = load_scene_set(f.path().string());
    for (std::size_t c = 0; c < set.conditions.size(); c += std::max<std::size_t>(1, set.conditions.size() / 3)) {
      expect_reads_back(set.conditions[c].scene, f.path().filename().string() + " condition " + std::to_string(c));
    }
    ++scenes;
  }
  EXPECT_GE(scenes, 10);
}

// The line of the first occurrence of `text` in `yaml`, 1-based.
int line_of(const std::string& yaml, const std::string& text) {
  const auto at = yaml.find(text);
  return 1 + static_cast<int>(std::count(yaml.begin(), yaml.begin() + static_cast<long>(at), '\n'));
}

const std::string kHead = "name: k\nseed: 1\nbunches:\n  - preset: table-red\n";

TEST(KeyTables, AnUnknownKeyFailsWithFileLineForEveryRegisteredType) {
  int checked = 0;
  const auto expect_unknown = [&](const std::string& yaml, const std::string& path) {
    const std::string m = scene_error(yaml);
    const std::string want = "scene.yaml:" + std::to_string(line_of(yaml, "not_a_key")) + ": unknown key '" + path + "'";
    EXPECT_NE(m.find(want), std::string::npos) << "want: " << want << "\ngot: " << m;
    ++checked;
  };
  const std::string rig = "rig:\n  type: turntable\n  views: 2\n";
  for (const auto& t : sensor_registry().types()) {
    expect_unknown(kHead + "sensor:\n  type: " + t + "\n  not_a_key: 1\n" + rig, "sensor.not_a_key");
  }
  for (const auto& t : rig_registry().types()) {
    expect_unknown(kHead + "sensor:\n  type: ideal\nrig:\n  type: " + t + "\n  not_a_key: 1\n", "rig.not_a_key");
  }
  const std::string scan = kHead + "sensor:\n  type: ideal\n" + rig;
  for (const auto& t : filter_registry().types()) {
    expect_unknown(scan + "pipeline:\n  cloud_filters:\n    - type: " + t + "\n      not_a_key: 1\n",
                   "pipeline.cloud_filters[0].not_a_key");
  }
  for (const auto& t : estimator_registry().types()) {
    if (t == "python" && !python_available()) continue;
    const std::string extra = t == "external" ? "    command: [x]\n"
                              : t == "python" ? "    module: json\n    function: dumps\n"
                                              : "";
    expect_unknown(scan + "estimators:\n  - type: " + t + "\n" + extra + "    not_a_key: 1\n",
                   "estimators[0].not_a_key");
  }
  for (const auto& t : registration_registry().types()) {
    expect_unknown(scan + "pipeline:\n  registration:\n    type: " + t + "\n    not_a_key: 1\n",
                   "pipeline.registration.not_a_key");
  }
  expect_unknown(scan + "pipeline:\n  not_a_key: 1\n", "pipeline.not_a_key");
  expect_unknown(scan + "background:\n  not_a_key: 1\n", "background.not_a_key");
  expect_unknown(scan + "foliage:\n  not_a_key: 1\n", "foliage.not_a_key");
  expect_unknown(kHead + "    not_a_key: 1\n", "bunches[0].not_a_key");
  EXPECT_GT(checked, 25);
}

TEST(KeyTables, AKeyTheChosenTypeOrMethodDoesNotReadFailsWithFileLine) {
  const std::string scan = kHead + "sensor:\n  type: kinect_v2\nrig:\n  type: turntable\n  views: 2\n";
  struct Case {
    std::string kind, yaml, key, condition;
  };
  const std::vector<Case> cases = {

      {"protocol", scan + "pipeline:\n  rois: [auto_r]\n", "pipeline.rois", "protocol: single_frame"},
      {"protocol", "protocol: single_frame\n" + scan + "pipeline:\n  min_points: 50\n", "pipeline.min_points",
       "protocol: multi_view"},
      {"protocol", "protocol: single_frame\n" + scan + "pipeline:\n  registration: plain_icp\n",
       "pipeline.registration", "protocol: multi_view"},
      {"sensor", kHead + "sensor:\n  type: kinect_v2\n  edge_filter: false\n  edge_abs: 0.01\nrig:\n  type: turntable\n",
       "sensor.edge_abs", "edge_filter: true"},
      {"sensor", kHead + "sensor:\n  type: stereo_rgb\n  plain_colour: [0, 1, 0]\nrig:\n  type: turntable\n",
       "sensor.plain_colour", "background: plain"},
      {"rig", kHead + "sensor:\n  type: ideal\nrig:\n  type: turntable\n  bottom_distance: 0.4\n",
       "rig.bottom_distance", "bottom_view: true"},
      {"estimator", scan + "estimators:\n  - type: poisson\n    solver: screened\n    depth: 9\n", "estimators[0].depth",
       "solver: pcl"},
      {"estimator", scan + "estimators:\n  - type: section_perimeters\n    angular_bins: 30\n",
       "estimators[0].angular_bins", "outline: angular"},
  };
  // The issue's example: a grouped registration's group size with the true poses, in
  // the pipeline (unknown there) and in the method's mapping (not a key of true_poses).
  for (const auto& [yaml, key] :
       std::vector<std::pair<std::string, std::string>>{
           {scan + "pipeline:\n  registration: true_poses\n  group_size: 7\n", "pipeline.group_size"},
           {scan + "pipeline:\n  registration:\n    type: true_poses\n    group_size: 7\n",
            "pipeline.registration.group_size"},
           {scan + "pipeline:\n  registration:\n    type: known_angle_icp\n    group_size: 7\n",
            "pipeline.registration.group_size"}}) {
    const std::string want = "scene.yaml:" + std::to_string(line_of(yaml, "group_size")) + ": unknown key '" + key + "'";
    EXPECT_NE(scene_error(yaml).find(want), std::string::npos) << "want: " << want << "\ngot: " << scene_error(yaml);
  }
  for (const auto& c : cases) {
    const std::string m = scene_error(c.yaml);
    const std::string leaf = c.key.substr(c.key.rfind('.') + 1);
    const std::string want = "scene.yaml:" + std::to_string(line_of(c.yaml, "  " + leaf + ":")) + ": '" + c.key +
                             "': is read only with " + c.condition;
    EXPECT_NE(m.find(want), std::string::npos) << c.kind << "\nwant: " << want << "\ngot: " << m;
  }
}

}  // namespace
}  // namespace grapebench
