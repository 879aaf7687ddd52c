// Triangulation of a rectified stereo match (seed 001 Eq. 8, with the principal point
// that the printed equation omits): Z = f B / d, X = (x - c_x) Z / f_x,
// Y = (y - c_y) Z / f_y, in the left camera's frame (x right, y down, z forward), m.
#pragma once

#include "algorithms/stereo_pair.h"
#include "synth/types.h"

namespace grapebench {

// (x, y): left pixel, px; disparity: px, > 0. Throws InputError for a disparity that
// is not positive and finite.
Vec3 triangulate_rectified(const StereoPair& camera, double x, double y, double disparity);

}  // namespace grapebench
