// What a volume estimator returns: the volume, its mesh where there is one, and
// diagnostics (Open3D's RegistrationResult style).
#pragma once

#include "synth/types.h"

#include <array>
#include <string>
#include <vector>

namespace grapebench {

struct VolumeEstimate {
  double volume = 0;  // m3
  // Surface the volume was measured on (empty when the method has none), metres.
  std::vector<Vec3> mesh_vertices;
  std::vector<std::array<int, 3>> mesh_triangles;
  bool watertight = false;      // the mesh is closed (the volume is its enclosed volume)
  std::size_t points_used = 0;
  std::string notes;            // method-specific diagnostics
};

}  // namespace grapebench
