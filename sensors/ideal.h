// The ideal sensor: the same pinhole rays, one per pixel centre, exact surface points,
// no noise, no range limits: the control every other model is compared with.
#pragma once

#include "sensors/sensor.h"

namespace grapebench {

struct IdealParams {
  int width = 512, height = 424;  // pixels, [16, 4096]
  double hfov_deg = 70.6;         // deg, [10, 150]
};
// The scene keys of `sensor: {type: ...}` for this model.
const ParamTable<IdealParams>& ideal_param_table();

// Exact pinhole capture from `camera`: one ray per pixel centre, no noise, no limits.
OrganisedCloud capture_exact(const RayScene& scene, const Camera& camera);

class IdealSensor : public Sensor {
 public:
  explicit IdealSensor(const IdealParams& p) : p_(p) {}
  std::string type() const override { return "ideal"; }
  Intrinsics intrinsics() const override { return intrinsics_from_hfov(p_.width, p_.height, p_.hfov_deg); }
  OrganisedCloud capture(const RayScene& scene, const Eigen::Isometry3d& pose, std::uint64_t seed) const override;
  nlohmann::ordered_json describe() const override;

 private:
  IdealParams p_;
};

}  // namespace grapebench
