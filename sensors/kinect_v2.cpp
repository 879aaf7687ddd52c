#include "sensors/kinect_v2.h"

#include "synth/rng.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <complex>

namespace grapebench {

Intrinsics KinectV2::intrinsics() const {
  return intrinsics_from_fov(p_.width, p_.height, p_.hfov_deg, p_.vfov_deg);
}

double KinectV2::axial_sigma(double z, double theta) const {
  const double t = std::min(theta, 0.5 * M_PI - 1e-3);
  const double g = 0.5 * M_PI - t;
  const double mm = p_.axial_a0 + p_.axial_a1 * z + p_.axial_a2 * z * z + p_.axial_a3 * z * std::sqrt(z) * t * t / (g * g);
  return std::max(0.0, mm) * 1e-3;
}

OrganisedCloud KinectV2::capture(const RayScene& scene, const Eigen::Isometry3d& pose, std::uint64_t seed) const {
  const Camera cam{intrinsics(), pose};
  const int W = cam.K.width, H = cam.K.height, n = p_.supersampling;
  const double lateral = p_.lateral_sd_px * p_.noise_scale;
  const double c = 299792458.0, k_phase = 4 * M_PI * p_.modulation_mhz * 1e6 / c;
  const double max_incidence = p_.max_incidence_deg * M_PI / 180;
  const BunchPixels bp = bunch_pixels(scene, cam);
  const bool bunch_visible = bp.visible;
  int bu0 = bp.u0, bv0 = bp.v0, bu1 = bp.u1, bv1 = bp.v1;
  const int margin = static_cast<int>(std::ceil(6 * lateral)) + 1;  // jitter can reach in
  bu0 = std::max(0, bu0 - margin);
  bv0 = std::max(0, bv0 - margin);
  bu1 = std::min(W, bu1 + margin);
  bv1 = std::min(H, bv1 + margin);

  OrganisedCloud out;
  out.resize(W, H);
  std::vector<float> depth(out.size(), 0.0f);  // raw depth of every return, 0 for none
  std::atomic<std::uint64_t> rays_cast{0};
  const Eigen::Matrix3d to_cam = pose.linear().transpose();

  for_rows(H, [&](int r0, int r1) {
    // Per-thread buffers, reused across rows and frames (no page faults per block).
    thread_local std::vector<Ray> rays;
    thread_local std::vector<Hit> hits;
    std::vector<double> jitter;  // per pixel: du, dv, axial normal draw
    for (int v = r0; v < r1; ++v) {
      // Pixels that can see the bunch go through Embree; with a background plane the
      // others are intersected analytically; without one they cannot return anything.
      const bool row_sees = bunch_visible && v >= bv0 && v < bv1;
      const bool plane = scene.background().has_value();
      if (!row_sees && !plane) continue;
      const int ua = plane ? 0 : bu0, ub = plane ? W : bu1;
      rays.clear();
      jitter.assign(3 * static_cast<std::size_t>(W), 0.0);
      // Inside the bunch's image rectangle a pixel's footprint is sampled by n x n rays;
      // outside it only the plane can be seen, where the blend of returns from one
      // plane is the centre ray's depth (to second order), so one ray suffices.
      const int sub_a = row_sees ? bu0 : ub, sub_b = row_sees ? bu1 : ub;
      for (int u = ua; u < ub; ++u) {
        const std::uint64_t k = 3 * (static_cast<std::uint64_t>(v) * W + u);
        const double du = lateral * hashed_normal(seed, k), dv = lateral * hashed_normal(seed, k + 1);
        jitter[3 * u] = du;
        jitter[3 * u + 1] = dv;
        jitter[3 * u + 2] = hashed_normal(seed, k + 2);
        if (u >= sub_a && u < sub_b) {
          for (int a = 0; a < n; ++a) {
            for (int b = 0; b < n; ++b) rays.push_back(cam.ray(u + (b + 0.5) / n + du, v + (a + 0.5) / n + dv));
          }
        }
      }
      const std::size_t nn = static_cast<std::size_t>(n) * n;
      hits.resize(rays.size());
      if (!rays.empty()) {
        scene.intersect(rays.data(), rays.size(), hits.data());
        rays_cast += rays.size();
      }
      for (int u = ua; u < ub; ++u) {
        const std::size_t idx = static_cast<std::size_t>(v) * W + u;
        const bool sampled = u >= sub_a && u < sub_b;
        Hit plane_only;
        Ray plane_ray;
        const Hit* sub;
        const Ray* sray;
        int count = n * n;
        if (sampled) {
          sub = &hits[static_cast<std::size_t>(u - sub_a) * nn];
          sray = &rays[static_cast<std::size_t>(u - sub_a) * nn];
        } else {
          plane_ray = cam.ray(u + 0.5 + jitter[3 * u], v + 0.5 + jitter[3 * u + 1]);
          plane_only = scene.background_hit(plane_ray);
          sub = &plane_only;
          sray = &plane_ray;
          count = 1;
        }
        // ToF pixel: sum of the returns' phasors, amplitude albedo cos(theta) / r^2.
        int dominant = -1, returns = 0;
        double wmax = 0;
        double w[64] = {};  // n <= 8
        for (int s = 0; s < count; ++s) {
          if (!sub[s].valid()) continue;
          ++returns;
          const double cos_t = std::max(0.0, -sub[s].normal.dot(sray[s].direction));
          const double albedo = sub[s].part == Part::Background && scene.background() ? scene.background()->albedo : 0.6;
          w[s] = albedo * cos_t / (sub[s].t * sub[s].t);
          if (w[s] > wmax) {
            wmax = w[s];
            dominant = s;
          }
        }
        if (dominant < 0 || static_cast<double>(returns) / count < p_.min_amplitude) continue;
        const Hit& dom = sub[dominant];
        double radial = dom.t;
        if (returns > 1) {
          std::complex<double> sum = 0;
          for (int s = 0; s < count; ++s) {
            if (w[s] > 0) sum += w[s] * std::polar(1.0, k_phase * (sub[s].t - dom.t));
          }
          radial += std::arg(sum) / k_phase;
        }
        // The pixel's footprint centre (lateral jitter included).
        const Ray centre = cam.ray(u + 0.5 + jitter[3 * u], v + 0.5 + jitter[3 * u + 1]);
        const Vec3 dir_cam = to_cam * centre.direction;
        const double z = radial * dir_cam.z();
        const double theta = std::acos(std::clamp(-dom.normal.dot(sray[dominant].direction), -1.0, 1.0));
        out.true_depth[idx] = static_cast<float>((to_cam * (dom.point - pose.translation())).z());
        out.label[idx] = static_cast<std::uint8_t>(dom.part);
        out.berry[idx] = dom.berry;
        depth[idx] = static_cast<float>(z);  // raw depth map: the edge filter sees every return
        if (z < p_.min_range || z > p_.max_range || theta > max_incidence) continue;
        const double zn = z + p_.noise_scale * axial_sigma(z, theta) * jitter[3 * u + 2];
        const Vec3 pc = dir_cam * (zn / dir_cam.z());
        out.xyz[idx] = pc.cast<float>();
        out.normal[idx] = (to_cam * dom.normal).cast<float>();
        out.rgb[idx] = shade(dom.colour, dom.normal, sray[dominant].direction);
        out.valid[idx] = 1;
        depth[idx] = static_cast<float>(zn);
      }
    }
  });
  out.rays_cast = rays_cast;

  if (p_.edge_filter) {
    std::vector<std::uint8_t> keep = out.valid;
    // Only pixels that returned can be dropped: without a background that is the
    // bunch's image rectangle.
    const bool plane = scene.background().has_value();
    const int fv0 = plane ? 0 : bv0, fv1 = plane ? H : (bunch_visible ? bv1 : 0);
    const int fu0 = plane ? 0 : bu0, fu1 = plane ? W : bu1;
    for (int v = fv0; v < fv1; ++v) {
      for (int u = fu0; u < fu1; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * W + u;
        if (!out.valid[i]) continue;
        const double tol = std::max(p_.edge_abs, p_.edge_rel * depth[i]);
        for (int dv = -1; dv <= 1 && keep[i]; ++dv) {
          for (int du = -1; du <= 1; ++du) {
            const int uu = u + du, vv = v + dv;
            if (uu < 0 || vv < 0 || uu >= W || vv >= H || (du == 0 && dv == 0)) continue;
            const std::size_t j = static_cast<std::size_t>(vv) * W + uu;
            if (depth[j] > 0 && std::abs(depth[j] - depth[i]) > tol) {
              keep[i] = 0;
              break;
            }
          }
        }
      }
    }
    out.valid = std::move(keep);
  }
  return out;
}

nlohmann::ordered_json KinectV2::describe() const {
  return {{"type", type()},
          {"width", p_.width},
          {"height", p_.height},
          {"hfov_deg", p_.hfov_deg},
          {"vfov_deg", p_.vfov_deg},
          {"min_range_m", p_.min_range},
          {"max_range_m", p_.max_range},
          {"noise_scale", p_.noise_scale},
          {"axial_mm", {p_.axial_a0, p_.axial_a1, p_.axial_a2, p_.axial_a3}},
          {"lateral_sd_px", p_.lateral_sd_px},
          {"max_incidence_deg", p_.max_incidence_deg},
          {"supersampling", p_.supersampling},
          {"modulation_mhz", p_.modulation_mhz},
          {"min_amplitude", p_.min_amplitude},
          {"edge_filter", p_.edge_filter},
          {"edge_abs_m", p_.edge_abs},
          {"edge_rel", p_.edge_rel}};
}

std::unique_ptr<Sensor> KinectV2::create(const ConfigNode& n) {
  KinectV2Params p;
  p.width = static_cast<int>(n.get_int("width", p.width, 16, 4096));
  p.height = static_cast<int>(n.get_int("height", p.height, 16, 4096));
  p.hfov_deg = n.get_real("hfov_deg", p.hfov_deg, 30, 120);
  p.vfov_deg = n.get_real("vfov_deg", p.vfov_deg, 20, 100);
  p.min_range = n.get_real("min_range", p.min_range, 0.1, 10);
  p.max_range = n.get_real("max_range", p.max_range, 0.2, 20);
  p.noise_scale = n.get_real("noise_scale", p.noise_scale, 0, 20);
  p.lateral_sd_px = n.get_real("lateral_sd_px", p.lateral_sd_px, 0, 5);
  p.max_incidence_deg = n.get_real("max_incidence_deg", p.max_incidence_deg, 10, 90);
  p.supersampling = static_cast<int>(n.get_int("supersampling", p.supersampling, 1, 8));
  p.modulation_mhz = n.get_real("modulation_mhz", p.modulation_mhz, 1, 200);
  p.min_amplitude = n.get_real("min_amplitude", p.min_amplitude, 0, 1);
  p.edge_filter = n.get_bool("edge_filter", p.edge_filter);
  p.edge_abs = n.get_real("edge_abs", p.edge_abs, 0.001, 0.5);
  p.edge_rel = n.get_real("edge_rel", p.edge_rel, 0, 0.5);
  if (p.min_range >= p.max_range) n.fail("min_range", "must be below max_range");
  return std::make_unique<KinectV2>(p);
}

}  // namespace grapebench
