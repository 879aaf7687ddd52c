// Scene files: the strict YAML documents `grapebench` runs (see scenes/README.md).
#pragma once

#include "sensors/rig.h"
#include "sensors/sensor.h"
#include "synth/params.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace grapebench {

struct BunchGroup {
  std::string preset;
  int count = 1;
  BunchParams params;  // the preset with the scene's overrides applied
};

struct Scene {
  std::string path;
  std::string name;
  std::uint64_t seed = 0;
  std::vector<BunchGroup> groups;
  // Capture (optional sections `sensor`, `rig`, `background`); built while parsing so
  // their errors name file:line before any work starts.
  std::shared_ptr<const Sensor> sensor;
  std::shared_ptr<const Rig> rig;
  BackgroundSpec background;
};

// One bunch to generate: its own seed is derived from the scene seed and its index,
// so bunches can be produced in any order on any number of threads.
struct BunchJob {
  std::string preset;
  int index = 0;
  std::uint64_t seed = 0;
  BunchParams params;
};

// Throws InputError naming file:line, key and allowed range; unknown keys are errors.
Scene load_scene(const std::string& path);
Scene parse_scene(const std::string& text, const std::string& name);
std::vector<BunchJob> bunch_jobs(const Scene& scene);

}  // namespace grapebench
