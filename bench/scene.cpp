#include "bench/scene.h"

#include "synth/rng.h"

#include <filesystem>

namespace grapebench {

namespace {

Scene read_scene(const ConfigNode& root, const std::string& path) {
  Scene s;
  s.path = path;
  s.name = root.get_string("name", std::filesystem::path(path).stem().string());
  if (!root.has("seed")) root.fail("seed", "missing: every scene names its seed (an unsigned integer)");
  s.seed = root.get_seed("seed", 0);
  if (!root.has("bunches")) root.fail("bunches", "missing: a list of {preset, count, parameters...}");
  for (const auto& node : root.children("bunches")) {
    BunchGroup g;
    g.preset = node.get_choice("preset", "table-red", preset_names());
    g.count = static_cast<int>(node.get_int("count", 1, 1, 100000));
    g.params = preset(g.preset);
    read_bunch_params(node, g.params);
    s.groups.push_back(std::move(g));
  }
  if (s.groups.empty()) root.fail("bunches", "the list is empty");
  if (root.has("sensor")) s.sensor = make_sensor(root.child("sensor"));
  if (root.has("rig")) s.rig = make_rig(root.child("rig"));
  if (root.has("background")) s.background = read_background(root.child("background"));
  if (s.rig && !s.sensor) root.fail("rig", "a rig needs a `sensor:` section");
  root.report_unused();
  return s;
}

}  // namespace

Scene load_scene(const std::string& path) { return read_scene(ConfigNode::load_file(path), path); }

Scene parse_scene(const std::string& text, const std::string& name) {
  return read_scene(ConfigNode::load_string(text, name), name);
}

std::vector<BunchJob> bunch_jobs(const Scene& scene) {
  std::vector<BunchJob> jobs;
  for (const auto& g : scene.groups) {
    for (int k = 0; k < g.count; ++k) {
      const int index = static_cast<int>(jobs.size());
      jobs.push_back({g.preset, index, derive_seed(scene.seed, static_cast<std::uint64_t>(index)), g.params});
    }
  }
  return jobs;
}

}  // namespace grapebench
