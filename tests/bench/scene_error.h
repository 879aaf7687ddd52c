// Test helper: the error a scene text gives when read as "scene.yaml" ("" if none).
#pragma once

#include "bench/scene_file.h"

#include <string>

namespace grapebench {

inline std::string scene_error(const std::string& yaml) {
  try {
    parse_scene_set(yaml, "scene.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace grapebench
