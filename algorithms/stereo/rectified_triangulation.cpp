#include "algorithms/stereo/rectified_triangulation.h"

#include <cmath>
#include <string>

#include "synth/config.h"

namespace grapebench {

Vec3 triangulate_rectified(const StereoPair& camera, double x, double y, double disparity) {
  if (!(disparity > 0) || !std::isfinite(disparity)) {
    throw InputError("triangulate_rectified: disparity " + std::to_string(disparity) + " px must be positive");
  }
  const double z = camera.fx * camera.baseline / disparity;
  return {(x - camera.cx) * z / camera.fx, (y - camera.cy) * z / camera.fy, z};
}

}  // namespace grapebench
