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

namespace {

// Calls f(a, b, in) for each maximal run [a, b) of pixels in [u0, u1) whose mask bytes
// (mask[u - u0]) are all `in`.
template <class F>
void for_each_run(const std::uint8_t* mask, int u0, int u1, F&& f) {
  for (int a = u0; a < u1;) {
    const bool in = mask[a - u0] != 0;
    int b = a + 1;
    while (b < u1 && (mask[b - u0] != 0) == in) ++b;
    f(a, b, in);
    a = b;
  }
}

}  // namespace

int KinectV2::jitter_margin() const { return static_cast<int>(std::ceil(6 * p_.lateral_sd_px * p_.noise_scale)) + 1; }

BunchPixels KinectV2::sampled_rect(const RayScene& scene, const Camera& cam) const {
  BunchPixels bp = bunch_pixels(scene, cam);
  const int margin = jitter_margin();  // jitter reaches in
  bp.u0 = std::max(0, bp.u0 - margin);
  bp.v0 = std::max(0, bp.v0 - margin);
  bp.u1 = std::min(cam.K.width, bp.u1 + margin);
  bp.v1 = std::min(cam.K.height, bp.v1 + margin);
  return bp;
}

void KinectV2::row_samples(int v, int ua, int ub, int sub_a, int sub_b, int width, std::uint64_t seed,
                           std::vector<double>& jitter, std::vector<double>& uv) const {
  const int n = p_.supersampling;
  const double lateral = p_.lateral_sd_px * p_.noise_scale;
  // Only [ua, ub) is read; lateral jitter is counters 3 k and 3 k + 1 of pixel k.
  jitter.resize(2 * static_cast<std::size_t>(width));
  const std::uint64_t k0 = 3 * static_cast<std::uint64_t>(v) * width;
  for (int u = ua; u < ub; ++u) {
    const std::uint64_t k = k0 + 3 * static_cast<std::uint64_t>(u);
    jitter[2 * u] = lateral > 0 ? lateral * hashed_normal_tabulated(seed, k) : 0.0;
    jitter[2 * u + 1] = lateral > 0 ? lateral * hashed_normal_tabulated(seed, k + 1) : 0.0;
  }
  uv.resize(2 * static_cast<std::size_t>(sub_b - sub_a) * n * n);
  double offset[8];  // sample centres within a pixel, px (n <= 8)
  for (int a = 0; a < n; ++a) offset[a] = (a + 0.5) / n;
  double* q = uv.data();
  for (int u = sub_a; u < sub_b; ++u) {
    const double ju = u + jitter[2 * u], jv = v + jitter[2 * u + 1];
    for (int a = 0; a < n; ++a) {
      for (int b = 0; b < n; ++b) {
        *q++ = ju + offset[b];
        *q++ = jv + offset[a];
      }
    }
  }
}

std::vector<Ray> KinectV2::traced_rays(const RayScene& scene, const Eigen::Isometry3d& pose, std::uint64_t seed) const {
  const Camera cam{intrinsics(), pose};
  const BunchPixels bp = sampled_rect(scene, cam);
  std::vector<Ray> rays;
  if (!bp.visible) return rays;
  const PixelRays ray_at = cam.pixel_rays();
  const std::vector<std::uint8_t> mask = scene_pixel_mask(scene, cam, bp, jitter_margin());
  std::vector<double> jitter, uv;
  for (int v = bp.v0; v < bp.v1; ++v) {
    const std::uint8_t* row_mask = &mask[static_cast<std::size_t>(v - bp.v0) * (bp.u1 - bp.u0)];
    for_each_run(row_mask, bp.u0, bp.u1, [&](int a, int b, bool in) {
      if (!in) return;
      row_samples(v, a, b, a, b, cam.K.width, seed, jitter, uv);
      for (std::size_t i = 0; i < uv.size(); i += 2) rays.push_back(ray_at(uv[i], uv[i + 1]));
    });
  }
  return rays;
}

OrganisedCloud KinectV2::capture(const RayScene& scene, const Eigen::Isometry3d& pose, std::uint64_t seed) const {
  const Camera cam{intrinsics(), pose};
  const int W = cam.K.width, H = cam.K.height, n = p_.supersampling;
  const double c = 299792458.0, k_phase = 4 * M_PI * p_.modulation_mhz * 1e6 / c;
  const double max_incidence = p_.max_incidence_deg * M_PI / 180;
  const BunchPixels bp = sampled_rect(scene, cam);
  const bool bunch_visible = bp.visible;
  const int bu0 = bp.u0, bv0 = bp.v0, bu1 = bp.u1, bv1 = bp.v1;

  OrganisedCloud out = frame_for(scene, cam, bp);
  // Raw depth of every return; set exactly where out.label is (no fill needed).
  raw_vector<float> depth(out.size());
  std::atomic<std::uint64_t> rays_cast{0};
  const Eigen::Matrix3d to_cam = pose.linear().transpose();
  const PixelRays ray_at = cam.pixel_rays();
  const Vec3 view_axis = pose.linear().col(2);  // world direction of the camera's z
  const double cos_max_incidence = std::cos(max_incidence);

  // One pixel from its returns sub[0, count): the ToF blend, noise and the outputs.
  const auto pixel = [&](int v, int u, const Hit* sub, int count, const std::vector<double>& jitter) {
    const std::size_t idx = static_cast<std::size_t>(v) * W + u;
    // ToF pixel: sum of the returns' phasors, amplitude albedo cos(theta) / r^2.
    int dominant = -1, returns = 0;
    double wmax = 0;
    double w[64];  // n <= 8
    for (int s = 0; s < count; ++s) {
      w[s] = 0;
      if (!sub[s].valid()) continue;
      ++returns;
      const double albedo = sub[s].part == Part::Background && scene.background() ? scene.background()->albedo : 0.6;
      w[s] = albedo * sub[s].cos_incidence / (sub[s].t * sub[s].t);
      if (w[s] > wmax) {
        wmax = w[s];
        dominant = s;
      }
    }
    if (dominant < 0 || static_cast<double>(returns) / count < p_.min_amplitude) return;
    const Hit& dom = sub[dominant];
    double radial = dom.t;
    if (returns > 1) {
      // Phase offsets of the returns from the dominant one. Where they are all
      // below 0.01 rad (one surface across the footprint), arg(sum w e^{i phi})
      // equals the weighted mean phase to O(phi^3), under 1e-7 m of depth here;
      // only mixed pixels at discontinuities need the full phasor sum.
      double phi_max = 0, wsum = 0, wphi = 0;
      for (int s = 0; s < count; ++s) {
        if (w[s] <= 0) continue;
        const double phi = k_phase * (sub[s].t - dom.t);
        phi_max = std::max(phi_max, std::abs(phi));
        wsum += w[s];
        wphi += w[s] * phi;
      }
      if (phi_max < 0.01) {
        radial += wphi / wsum / k_phase;
      } else {
        std::complex<double> sum = 0;
        for (int s = 0; s < count; ++s) {
          if (w[s] > 0) sum += w[s] * std::polar(1.0, k_phase * (sub[s].t - dom.t));
        }
        radial += std::arg(sum) / k_phase;
      }
    }
    // The pixel's footprint centre (lateral jitter included), in the camera frame:
    // (x, y, 1) scaled so that z is the depth.
    const double xc = (u + 0.5 + jitter[2 * u] - cam.K.cx) / cam.K.fx;
    const double yc = (v + 0.5 + jitter[2 * u + 1] - cam.K.cy) / cam.K.fy;
    const double z = radial / std::sqrt(xc * xc + yc * yc + 1);
    const double cos_theta = std::min(1.0, dom.cos_incidence);
    out.true_depth[idx] = static_cast<float>(view_axis.dot(dom.point - pose.translation()));
    out.label[idx] = static_cast<std::uint8_t>(dom.part);
    out.berry[idx] = dom.berry;
    depth[idx] = static_cast<float>(z);  // raw depth map: the edge filter sees every return
    if (z < p_.min_range || z > p_.max_range || cos_theta < cos_max_incidence) return;
    // The axial draw is made only for returns (counter 3 k + 2 of the pixel).
    const std::uint64_t k3 = 3 * (static_cast<std::uint64_t>(v) * W + u);
    const double zn = z + p_.noise_scale * axial_sigma(z, std::acos(cos_theta)) * hashed_normal_tabulated(seed, k3 + 2);
    const Vec3 pc(xc * zn, yc * zn, zn);
    out.xyz[idx] = pc.cast<float>();
    out.normal[idx] = (to_cam * dom.normal).cast<float>();
    out.rgb[idx] = shade(dom.colour, dom.cos_incidence);
    out.valid[idx] = 1;
    depth[idx] = static_cast<float>(zn);
  };

  // The rectangle's pixels whose footprints can meet anything Embree holds; the others
  // can see at most the plane (with the same 6 sd reach of the jitter as the rectangle).
  const std::vector<std::uint8_t> mask = scene_pixel_mask(scene, cam, bp, jitter_margin());
  const std::size_t nn = static_cast<std::size_t>(n) * n;
  const bool plane = scene.background().has_value();
  for_rows(H, [&](int r0, int r1) {
    // Per-thread buffers, reused across rows and frames (no page faults per block).
    thread_local std::vector<double> uv;  // sample points (u, v), pixels
    thread_local std::vector<Hit> hits;
    std::vector<double> jitter;  // per pixel: lateral du, dv (px)
    std::uint64_t block_rays = 0;
    // n x n Embree hits of the samples uv[2 first, 2 (first + count)) into hits[first...].
    const auto trace = [&](std::size_t first, std::size_t count) {
      scene.intersect_image_points(ray_at, uv.data() + 2 * first, count, hits.data() + first);
      block_rays += count;
    };
    for (int v = r0; v < r1; ++v) {
      const bool row_sees = bunch_visible && v >= bv0 && v < bv1;
      const std::uint8_t* row_mask = row_sees ? &mask[static_cast<std::size_t>(v - bv0) * (bu1 - bu0)] : nullptr;
      if (!plane) {
        // Without a plane only the masked runs can return anything: they alone are sampled.
        if (!row_sees) continue;
        for_each_run(row_mask, bu0, bu1, [&](int a, int b, bool in) {
          if (!in) return;
          row_samples(v, a, b, a, b, W, seed, jitter, uv);
          hits.resize(std::max(hits.size(), uv.size() / 2));
          trace(0, uv.size() / 2);
          for (int u = a; u < b; ++u) pixel(v, u, &hits[static_cast<std::size_t>(u - a) * nn], n * n, jitter);
        });
        continue;
      }
      // With a plane every pixel returns. Inside the bunch's image rectangle a pixel's
      // footprint is sampled by n x n rays; outside it only the plane can be seen, where
      // the blend of returns from one plane is the centre ray's depth (to second order),
      // so one ray suffices. The rectangle's unmasked samples meet the plane alone:
      // intersected analytically, the same rays and so the same hits as through Embree.
      const int sub_a = row_sees ? bu0 : W, sub_b = row_sees ? bu1 : W;
      row_samples(v, 0, W, sub_a, sub_b, W, seed, jitter, uv);
      hits.resize(std::max(hits.size(), uv.size() / 2));
      if (row_sees) {
        for_each_run(row_mask, bu0, bu1, [&](int a, int b, bool in) {
          const std::size_t first = static_cast<std::size_t>(a - bu0) * nn, count = static_cast<std::size_t>(b - a) * nn;
          if (in) {
            trace(first, count);
          } else {
            for (std::size_t i = first; i < first + count; ++i) hits[i] = scene.background_hit(ray_at(uv[2 * i], uv[2 * i + 1]));
          }
        });
      }
      for (int u = 0; u < W; ++u) {
        if (u >= sub_a && u < sub_b) {
          pixel(v, u, &hits[static_cast<std::size_t>(u - sub_a) * nn], n * n, jitter);
        } else {
          const Hit h = scene.background_hit(ray_at(u + 0.5 + jitter[2 * u], v + 0.5 + jitter[2 * u + 1]));
          pixel(v, u, &h, 1, jitter);
        }
      }
    }
    rays_cast += block_rays;
  });
  out.rays_cast = rays_cast;

  if (p_.edge_filter) {
    std::vector<std::size_t> drop;  // decided on the unfiltered map, applied after
    const auto none = static_cast<std::uint8_t>(Part::None);
    // Only pixels that returned can be dropped: without a background that is the
    // bunch's image rectangle.
    const int fv0 = plane ? 0 : bv0, fv1 = plane ? H : (bunch_visible ? bv1 : 0);
    const int fu0 = plane ? 0 : bu0, fu1 = plane ? W : bu1;
    for (int v = fv0; v < fv1; ++v) {
      for (int u = fu0; u < fu1; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * W + u;
        if (!out.valid[i]) continue;
        const double tol = std::max(p_.edge_abs, p_.edge_rel * depth[i]);
        bool edge = false;
        for (int dv = -1; dv <= 1 && !edge; ++dv) {
          for (int du = -1; du <= 1; ++du) {
            const int uu = u + du, vv = v + dv;
            if (uu < 0 || vv < 0 || uu >= W || vv >= H || (du == 0 && dv == 0)) continue;
            const std::size_t j = static_cast<std::size_t>(vv) * W + uu;
            if (out.label[j] != none && std::abs(depth[j] - depth[i]) > tol) {
              edge = true;
              break;
            }
          }
        }
        if (edge) drop.push_back(i);
      }
    }
    for (const std::size_t i : drop) out.valid[i] = 0;
  }
  return out;
}

nlohmann::ordered_json KinectV2::describe() const { return with_type(type(), kinect_v2_param_table().to_json(p_)); }

const ParamTable<KinectV2Params>& kinect_v2_param_table() {
  using P = KinectV2Params;
  static const ParamTable<P> table =
      ParamTable<P>()
          .integer("width", "px", &P::width, 16, 4096, "depth image width (Kinect v2: 512)")
          .integer("height", "px", &P::height, 16, 4096, "depth image height (Kinect v2: 424)")
          .real("hfov_deg", "deg", &P::hfov_deg, 30, 120, "horizontal field of view (Kinect v2: 70.6)")
          .real("vfov_deg", "deg", &P::vfov_deg, 20, 100, "vertical field of view (Kinect v2: 60)")
          .real("min_range", "m", &P::min_range, 0.1, 10, "no return nearer (seed 000: 0.5-4.5 m)")
          .real("max_range", "m", &P::max_range, 0.2, 20, "no return further")
          .real("noise_scale", "-", &P::noise_scale, 0, 20, "0 ideal geometry, 1 nominal, >1 worse")
          .real("axial_a0", "mm", &P::axial_a0, -100, 100,
                "axial noise sigma_z = a0 + a1 z + a2 z^2 + a3 z^1.5 theta^2/(pi/2-theta)^2 (Fankhauser 2015)")
          .real("axial_a1", "mm/m", &P::axial_a1, -100, 100, "axial noise, linear term")
          .real("axial_a2", "mm/m2", &P::axial_a2, -100, 100, "axial noise, quadratic term")
          .real("axial_a3", "mm", &P::axial_a3, -100, 100, "axial noise, incidence term")
          .real("lateral_sd_px", "px", &P::lateral_sd_px, 0, 5, "sd of a pixel footprint's position (Fankhauser 2015)")
          .real("max_incidence_deg", "deg", &P::max_incidence_deg, 10, 90, "no return at more grazing angles")
          .integer("supersampling", "count", &P::supersampling, 1, 8,
                   "n x n rays per pixel blended as ToF phasors (mixed pixels)")
          .real("modulation_mhz", "MHz", &P::modulation_mhz, 1, 200, "modulation frequency of the phasor blend")
          .real("min_amplitude", "-", &P::min_amplitude, 0, 1, "pixels with less of a full return are dropped")
          .boolean("edge_filter", &P::edge_filter, "drop pixels on depth edges, as the official driver does")
          .real("edge_abs", "m", &P::edge_abs, 0.001, 0.5, "edge filter: absolute depth jump")
          .when("edge_filter: true", [](const P& p) { return p.edge_filter; })
          .real("edge_rel", "-", &P::edge_rel, 0, 0.5, "edge filter: depth jump relative to z")
          .when("edge_filter: true", [](const P& p) { return p.edge_filter; })
          .validate([](const P& p, const ConfigNode& n) {
            if (p.min_range >= p.max_range) n.fail("min_range", "must be below max_range");
          });
  return table;
}

}  // namespace grapebench
