#include "sensors/ideal.h"

#include <atomic>

namespace grapebench {

OrganisedCloud IdealSensor::capture(const RayScene& scene, const Eigen::Isometry3d& pose, std::uint64_t) const {
  return capture_exact(scene, Camera{intrinsics(), pose});
}

OrganisedCloud capture_exact(const RayScene& scene, const Camera& cam) {
  const Eigen::Isometry3d& pose = cam.pose;
  const int W = cam.K.width, H = cam.K.height;
  const BunchPixels bp = bunch_pixels(scene, cam);
  const bool bunch_visible = bp.visible;
  const int bu0 = bp.u0, bv0 = bp.v0, bu1 = bp.u1, bv1 = bp.v1;
  const Eigen::Matrix3d to_cam = pose.linear().transpose();
  OrganisedCloud out = frame_for(scene, cam, bp);
  std::atomic<std::uint64_t> rays_cast{0};
  for_rows(H, [&](int r0, int r1) {
    // Per-thread buffers, reused across rows and frames (no page faults per block).
    thread_local std::vector<double> uv;
    thread_local std::vector<Hit> hits;
    for (int v = r0; v < r1; ++v) {
      const bool row = bunch_visible && v >= bv0 && v < bv1;
      const bool plane = scene.background().has_value();
      if (!row && !plane) continue;  // nothing can return light
      const int ua = plane ? 0 : bu0, ub = plane ? W : bu1;
      rays_cast += trace_row(scene, cam, v, ua, ub, bu0, bu1, row, uv, hits);
      for (int u = ua; u < ub; ++u) {
        const Hit& h = hits[u];
        if (!h.valid()) continue;
        const std::size_t idx = static_cast<std::size_t>(v) * W + u;
        const Vec3 pc = to_cam * (h.point - pose.translation());
        out.xyz[idx] = pc.cast<float>();
        out.normal[idx] = (to_cam * h.normal).cast<float>();
        out.rgb[idx] = shade(h.colour, h.cos_incidence);
        out.label[idx] = static_cast<std::uint8_t>(h.part);
        out.berry[idx] = h.berry;
        out.valid[idx] = 1;
        out.true_depth[idx] = static_cast<float>(pc.z());
      }
    }
  });
  out.rays_cast = rays_cast;
  return out;
}

nlohmann::ordered_json IdealSensor::describe() const { return with_type(type(), ideal_param_table().to_json(p_)); }

const ParamTable<IdealParams>& ideal_param_table() {
  using P = IdealParams;
  static const ParamTable<P> table = ParamTable<P>()
                                         .integer("width", "px", &P::width, 16, 4096, "image width")
                                         .integer("height", "px", &P::height, 16, 4096, "image height")
                                         .real("hfov_deg", "deg", &P::hfov_deg, 10, 150, "horizontal field of view");
  return table;
}

}  // namespace grapebench
