// Intel RealSense D435 (active infrared stereo), the sensor of seed 003.
#pragma once

#include "sensors/sensor.h"

namespace grapebench {

struct D435Params {
  int width = 848, height = 480;  // pixels; 1280 x 720 also supported
  double hfov_deg = 87;           // deg, [40, 120] (D435 depth: 87 x 58)
  double baseline = 0.050;        // m, [0.01, 0.5]: left to right imager
  // Subpixel disparity noise sd (RealSense tuning guide: 0.08 px typical), so
  // sigma_z = z^2 s / (f B). [0, 2]
  double subpixel_sd = 0.08;
  double disparity_step = 1.0 / 32;  // px, disparity quantisation (5-bit subpixel); [0, 1]
  double max_disparity = 126;        // px: MinZ = f B / max_disparity; [8, 1024]
  double max_range = 10;             // m, [0.5, 65]
  // Infrared projector position in the left imager's frame (x right), m. Points it
  // cannot light return nothing. Approximate placement between the imagers.
  double projector_x = 0.025, projector_y = 0.0;
  bool require_projector = true;
  double noise_scale = 1.0;  // [0, 20]
};
// The scene keys of `sensor: {type: ...}` for this model.
const ParamTable<D435Params>& d435_param_table();

class D435 : public Sensor {
 public:
  explicit D435(const D435Params& p) : p_(p) {}
  std::string type() const override { return "d435"; }
  Intrinsics intrinsics() const override { return intrinsics_from_hfov(p_.width, p_.height, p_.hfov_deg); }
  OrganisedCloud capture(const RayScene& scene, const Eigen::Isometry3d& pose, std::uint64_t seed) const override;
  nlohmann::ordered_json describe() const override;
  double min_z() const { return intrinsics().fx * p_.baseline / p_.max_disparity; }
  // Depth sd (m) at depth z, before quantisation: z^2 s / (f B).
  double depth_sigma(double z) const { return z * z * p_.subpixel_sd * p_.noise_scale / (intrinsics().fx * p_.baseline); }
  const D435Params& params() const { return p_; }

 private:
  D435Params p_;
};

}  // namespace grapebench
