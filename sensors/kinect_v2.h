// Kinect v2 (time of flight), the sensor of seeds 000 and 002.
#pragma once

#include "sensors/sensor.h"

namespace grapebench {

struct KinectV2Params {
  int width = 512, height = 424;   // pixels (Kinect v2 depth camera)
  double hfov_deg = 70.6;          // deg, [30, 120]
  double vfov_deg = 60.0;          // deg, [20, 100]
  double min_range = 0.5;          // m, [0.1, 10]: no return nearer (seed 000: 0.5-4.5 m)
  double max_range = 4.5;          // m, [0.2, 20]
  double noise_scale = 1.0;        // 0 ideal geometry, 1 nominal, >1 worse; [0, 20]
  // Axial noise, Fankhauser et al. 2015 (z in m, theta incidence angle, result in mm):
  //   sigma_z = a0 + a1 z + a2 z^2 + a3 z^1.5 theta^2 / (pi/2 - theta)^2
  // 1.3 mm at 1 m head-on, within the 2 mm seed 000 states.
  double axial_a0 = 1.5, axial_a1 = -0.5, axial_a2 = 0.3, axial_a3 = 0.1;  // mm
  // Lateral noise: sd of the pixel's footprint position, pixels (Fankhauser et al.
  // 2015 report about one pixel or less, nearly constant with distance). [0, 5]
  double lateral_sd_px = 0.5;
  double max_incidence_deg = 80;  // deg, [10, 90]: no return at more grazing angles
  // Mixed ("flying") pixels: each pixel's footprint is sampled by n x n rays and their
  // returns blended as a ToF pixel does, by summing phasors of amplitude
  // albedo cos(theta) / r^2 at the modulation frequency. [1, 8]
  int supersampling = 2;
  double modulation_mhz = 16;   // MHz, [1, 200]: lowest Kinect v2 frequency (unambiguous)
  double min_amplitude = 0.25;  // fraction of a full-pixel return below which the pixel is dropped, [0, 1]
  // Edge filter like the official driver's: drop pixels whose depth differs from an
  // 8-neighbour by more than max(edge_abs, edge_rel z). On by default.
  bool edge_filter = true;
  double edge_abs = 0.015;  // m, [0.001, 0.5]
  double edge_rel = 0.02;   // -, [0, 0.5]
};
// The scene keys of `sensor: {type: ...}` for this model.
const ParamTable<KinectV2Params>& kinect_v2_param_table();

class KinectV2 : public Sensor {
 public:
  explicit KinectV2(const KinectV2Params& p) : p_(p) {}
  std::string type() const override { return "kinect_v2"; }
  Intrinsics intrinsics() const override;
  OrganisedCloud capture(const RayScene& scene, const Eigen::Isometry3d& pose, std::uint64_t seed) const override;
  nlohmann::ordered_json describe() const override;
  // The model's axial noise sd, m, at depth z (m) and incidence theta (rad), before noise_scale.
  double axial_sigma(double z, double theta) const;
  // Every ray a capture without background traces through Embree, in order: the
  // benchmark's raw Embree loop casts exactly these.
  std::vector<Ray> traced_rays(const RayScene& scene, const Eigen::Isometry3d& pose, std::uint64_t seed) const;
  const KinectV2Params& params() const { return p_; }

 private:
  // The pixels sampled n x n: the bunch's image rectangle grown by the reach of the
  // lateral jitter. Only those of its pixels that scene_pixel_mask marks go through
  // Embree; without a background the others are not sampled at all (they cannot
  // return), with one their samples meet the plane alone.
  BunchPixels sampled_rect(const RayScene& scene, const Camera& cam) const;
  // The reach of the lateral jitter, px: 6 sd, plus the footprint's own pixel.
  int jitter_margin() const;
  // Row v: lateral jitter of pixels [ua, ub) (jitter: 2 per pixel, px) and the n x n
  // footprint sample points of pixels [sub_a, sub_b) (uv: 2 per sample, px).
  void row_samples(int v, int ua, int ub, int sub_a, int sub_b, int width, std::uint64_t seed,
                   std::vector<double>& jitter, std::vector<double>& uv) const;
  KinectV2Params p_;
};

}  // namespace grapebench
