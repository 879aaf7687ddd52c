#include "sensors/d435.h"

#include "synth/rng.h"

#include <atomic>
#include <cmath>

namespace grapebench {

OrganisedCloud D435::capture(const RayScene& scene, const Eigen::Isometry3d& pose, std::uint64_t seed) const {
  const Camera cam{intrinsics(), pose};
  const int W = cam.K.width, H = cam.K.height;
  const double fB = cam.K.fx * p_.baseline;
  const Vec3 right = pose * Vec3(p_.baseline, 0, 0);
  const Vec3 projector = pose * Vec3(p_.projector_x, p_.projector_y, 0);
  const BunchPixels bp = bunch_pixels(scene, cam);
  const bool bunch_visible = bp.visible;
  const int bu0 = bp.u0, bv0 = bp.v0, bu1 = bp.u1, bv1 = bp.v1;
  const Vec3 bc = scene.bounds_centre();
  const double br = scene.bounds_radius();
  // Whether a segment from a sensor to a hit can pass through the bunch at all (else
  // nothing can block it). A bunch hit lies inside the bunch's bounding ball, so its
  // segments always can; only background hits need the distance test.
  const bool has_bunch = scene.has_bunch();
  auto may_block = [&](const Vec3& a, const Hit& h) {
    if (!has_bunch) return false;
    return h.part != Part::Background || point_segment_distance_sq(bc, a, h.point) <= br * br;
  };
  const Eigen::Matrix3d to_cam = pose.linear().transpose();
  OrganisedCloud out = frame_for(scene, cam, bp);
  std::atomic<std::uint64_t> rays_cast{0};

  for_rows(H, [&](int r0, int r1) {
    // Per-thread buffers, reused across rows and frames (no page faults per block).
    thread_local std::vector<double> uv;
    thread_local std::vector<Hit> hits;
    thread_local std::vector<Vec3> from, to;
    thread_local std::vector<std::size_t> who;
    thread_local std::vector<char> blocked, shadow;
    for (int v = r0; v < r1; ++v) {
      const bool row_sees_bunch = bunch_visible && v >= bv0 && v < bv1;
      const bool plane = scene.background().has_value();
      if (!row_sees_bunch && !plane) continue;  // nothing can return light
      const int ua = plane ? 0 : bu0, ub = plane ? W : bu1;
      rays_cast += trace_row(scene, cam, v, ua, ub, bu0, bu1, row_sees_bunch, uv, hits);
      // Occlusion shadows: the point must be seen by the right imager and lit by
      // the projector; only segments that can cross the bunch are traced.
      from.clear();
      to.clear();
      who.clear();
      for (int u = ua; u < ub; ++u) {
        if (!hits[u].valid()) continue;
        if (may_block(right, hits[u])) {
          from.push_back(right);
          to.push_back(hits[u].point);
          who.push_back(u);
        }
        if (p_.require_projector && may_block(projector, hits[u])) {
          from.push_back(projector);
          to.push_back(hits[u].point);
          who.push_back(u);
        }
      }
      scene.occluded(from, to, blocked);
      rays_cast += from.size();
      shadow.assign(W, 0);
      for (std::size_t k = 0; k < who.size(); ++k) shadow[who[k]] |= blocked[k];
      for (int u = ua; u < ub; ++u) {
        const std::size_t idx = static_cast<std::size_t>(v) * W + u;
        const Hit& h = hits[u];
        if (!h.valid()) continue;
        const Vec3 p_cam = to_cam * (h.point - pose.translation());
        const double z = p_cam.z();
        out.true_depth[idx] = static_cast<float>(z);
        out.label[idx] = static_cast<std::uint8_t>(h.part);
        out.berry[idx] = h.berry;
        if (shadow[u]) continue;
        double d = fB / z + p_.noise_scale * p_.subpixel_sd * hashed_normal_tabulated(seed, idx);
        if (p_.disparity_step > 0) d = std::round(d / p_.disparity_step) * p_.disparity_step;
        if (d <= 0 || d > p_.max_disparity) continue;  // nearer than MinZ, or no match
        const double zd = fB / d;
        if (zd > p_.max_range) continue;
        out.xyz[idx] = (p_cam * (zd / z)).cast<float>();
        out.normal[idx] = (to_cam * h.normal).cast<float>();
        out.rgb[idx] = shade(h.colour, h.cos_incidence);
        out.valid[idx] = 1;
      }
    }
  });
  out.rays_cast = rays_cast;
  return out;
}

nlohmann::ordered_json D435::describe() const { return with_type(type(), d435_param_table().to_json(p_)); }

const ParamTable<D435Params>& d435_param_table() {
  using P = D435Params;
  static const ParamTable<P> table =
      ParamTable<P>()
          .integer("width", "px", &P::width, 16, 4096, "depth image width (D435: 848 or 1280)")
          .integer("height", "px", &P::height, 16, 4096, "depth image height (D435: 480 or 720)")
          .real("hfov_deg", "deg", &P::hfov_deg, 40, 120, "horizontal field of view (D435 depth: 87)")
          .real("baseline", "m", &P::baseline, 0.01, 0.5, "left to right imager")
          .real("subpixel_sd", "px", &P::subpixel_sd, 0, 2,
                "disparity noise sd, sigma_z = z^2 s / (f B) (RealSense tuning guide: 0.08)")
          .real("disparity_step", "px", &P::disparity_step, 0, 1, "disparity quantisation (5-bit subpixel: 1/32)")
          .real("max_disparity", "px", &P::max_disparity, 8, 1024, "search range: MinZ = f B / max_disparity")
          .real("max_range", "m", &P::max_range, 0.5, 65, "no return further")
          .real("projector_x", "m", &P::projector_x, -0.5, 0.5, "infrared projector in the left imager's frame, x")
          .real("projector_y", "m", &P::projector_y, -0.5, 0.5, "infrared projector, y")
          .boolean("require_projector", &P::require_projector, "points the projector cannot light return nothing")
          .real("noise_scale", "-", &P::noise_scale, 0, 20, "0 ideal geometry, 1 nominal, >1 worse");
  return table;
}

}  // namespace grapebench
