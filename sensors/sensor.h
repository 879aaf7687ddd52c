// Sensor models and their registry (scene files name them by `type`).
#pragma once

#include "sensors/camera.h"
#include "sensors/cloud.h"
#include "sensors/ray_scene.h"
#include "synth/config.h"
#include "synth/param_table.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace grapebench {

class Sensor {
 public:
  virtual ~Sensor() = default;
  virtual std::string type() const = 0;
  virtual Intrinsics intrinsics() const = 0;
  // One frame from a camera at `pose` (camera to world). Every random draw comes
  // from `seed` and the pixel index, so the frame is the same at any thread count.
  virtual OrganisedCloud capture(const RayScene& scene, const Eigen::Isometry3d& pose,
                                 std::uint64_t seed) const = 0;
  // All parameters with their values, for the manifest.
  virtual nlohmann::ordered_json describe() const = 0;
  // Sensors whose keys are equal and not empty take the same frames but for what the
  // key leaves out (stereo_rgb's `ray` renderer: the light), and capture_together
  // gives them faster than one by one (a sweep over seed 001's lights). Empty, the
  // default: each is captured alone.
  virtual std::string together_key() const { return {}; }
  // The frames of one view by `sensors` (each with this one's together_key), in their
  // order, each the same as its own capture(). The default captures them in turn.
  virtual std::vector<OrganisedCloud> capture_together(std::span<const Sensor* const> sensors, const RayScene& scene,
                                                       const Eigen::Isometry3d& pose, std::uint64_t seed) const;
};


// Helpers shared by the models.
// Shaded colour of a point from the cosine of incidence (Hit::cos_incidence). Inline:
// once per point.
inline std::array<std::uint8_t, 3> shade(const Rgb& colour, double cos_incidence) {
  // Light at the camera: ambient plus Lambert; rounded half up by truncation.
  const float k = 0.35f + 0.65f * static_cast<float>(std::max(0.0, cos_incidence));
  auto byte = [k](float x) { return static_cast<std::uint8_t>(std::clamp(x * k, 0.0f, 1.0f) * 255.0f + 0.5f); };
  return {byte(colour.r), byte(colour.g), byte(colour.b)};
}
inline double point_segment_distance_sq(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).squaredNorm();
}
// Pixel rectangle [u0, u1) x [v0, v1) that can see the bunch from `cam`; `visible` is
// false when it cannot be seen at all (or the scene holds only a background).
struct BunchPixels {
  bool visible = false;
  int u0 = 0, v0 = 0, u1 = 0, v1 = 0;
};
BunchPixels bunch_pixels(const RayScene& scene, const Camera& cam);
// Which pixels of the rectangle bp can see anything Embree holds: one byte per pixel,
// (bp.v1 - bp.v0) x (bp.u1 - bp.u0), row-major, 1 where a footprint widened by
// `margin` px may meet a berry, stem, leaf or cane. Conservative: every primitive is
// bounded by balls (a stem or cane by one per piece of its axis no longer than its
// diameter or the pixel pitch at its nearest depth, a leaf triangle by one about its
// centroid) and the image rectangle of each ball is marked.
std::vector<std::uint8_t> scene_pixel_mask(const RayScene& scene, const Camera& cam, const BunchPixels& bp,
                                           int margin);
// A frame of `cam`'s size whose valid and label maps can change only in the rows that
// can return light: all of them with a background plane, else those of `bp`.
OrganisedCloud frame_for(const RayScene& scene, const Camera& cam, const BunchPixels& bp);

// One ray per pixel centre of row v over pixels [ua, ub): Embree for [bu0, bu1) when
// `sees_bunch`, the analytic background elsewhere; hits[u] for pixel u (`uv` is
// scratch). Returns the rays traced by Embree.
std::size_t trace_row(const RayScene& scene, const Camera& cam, int v, int ua, int ub, int bu0, int bu1,
                      bool sees_bunch, std::vector<double>& uv, std::vector<Hit>& hits);
// Parallel loop over image rows in fixed blocks (deterministic result).
void for_rows(int height, const std::function<void(int v0, int v1)>& body);

}  // namespace grapebench
