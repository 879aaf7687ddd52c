// Scene files: the strict YAML documents `grapebench` runs (see scenes/README.md):
// the top-level keys (name, seed, protocol), every section through bench/scene.h's
// readers, and the sweep.
#pragma once

#include "bench/scene.h"

#include <cstddef>
#include <string>

namespace grapebench {

// Throws InputError naming file:line, key and allowed range; unknown keys are errors.
Scene load_scene(const std::string& path);
Scene parse_scene(const std::string& text, const std::string& name);
// A scene with its sweep expanded (the product of the axes, first axis slowest).
SceneSet load_scene_set(const std::string& path);
SceneSet parse_scene_set(const std::string& text, const std::string& name);
// A scene file's text: a regular file of at most kMaxSceneFileBytes (the largest in
// scenes/ is 3 KB), never a FIFO or device; InputError otherwise.
inline constexpr std::size_t kMaxSceneFileBytes = std::size_t{1} << 20;
std::string read_scene_text(const std::string& path);

}  // namespace grapebench
