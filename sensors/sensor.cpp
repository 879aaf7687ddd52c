#include "sensors/sensor.h"


#include <tbb/parallel_for.h>

#include <cmath>

namespace grapebench {

std::vector<OrganisedCloud> Sensor::capture_together(std::span<const Sensor* const> sensors, const RayScene& scene,
                                                     const Eigen::Isometry3d& pose, std::uint64_t seed) const {
  std::vector<OrganisedCloud> out;
  out.reserve(sensors.size());
  for (const Sensor* s : sensors) out.push_back(s->capture(scene, pose, seed));
  return out;
}

BunchPixels bunch_pixels(const RayScene& scene, const Camera& cam) {
  BunchPixels b;
  b.visible = scene.has_bunch() && cam.ball_pixels(scene.bounds_centre(), scene.bounds_radius(), b.u0, b.v0, b.u1, b.v1);
  return b;
}

std::vector<std::uint8_t> scene_pixel_mask(const RayScene& scene, const Camera& cam, const BunchPixels& bp,
                                           int margin) {
  const int w = bp.u1 - bp.u0, h = bp.v1 - bp.v0;
  std::vector<std::uint8_t> mask(bp.visible && w > 0 && h > 0 ? static_cast<std::size_t>(w) * h : 0, 0);
  if (mask.empty()) return mask;
  const Eigen::Isometry3d to_cam = cam.pose.inverse();
  // Each ball's rectangle goes in as four corners of a 2D difference array ((h + 1) x
  // (w + 1)); one prefix-sum pass then counts the rectangles over each pixel. Thousands
  // of small rectangles cost O(1) each instead of a row fill each.
  const std::size_t stride = static_cast<std::size_t>(w) + 1;
  std::vector<int> corners(stride * (static_cast<std::size_t>(h) + 1), 0);
  const auto mark_camera_frame = [&](const Vec3& p, double radius) {
    int u0, v0, u1, v1;
    if (!cam.ball_pixels_camera_frame(p, radius, u0, v0, u1, v1)) return;
    u0 = std::max(u0 - margin, bp.u0) - bp.u0;
    u1 = std::min(u1 + margin, bp.u1) - bp.u0;
    v0 = std::max(v0 - margin, bp.v0) - bp.v0;
    v1 = std::min(v1 + margin, bp.v1) - bp.v0;
    if (u0 >= u1 || v0 >= v1) return;
    ++corners[v0 * stride + u0];
    --corners[v0 * stride + u1];
    --corners[v1 * stride + u0];
    ++corners[v1 * stride + u1];
  };
  const double f = std::max(cam.K.fx, cam.K.fy);
  const auto mark_cylinder = [&](const Stem& s) {
    // Balls around pieces of the axis: a piece of length l is inside a ball of radius
    // sqrt((l/2)^2 + r^2). Pieces are no longer than the diameter or than a pixel's
    // pitch at the stem's nearest depth, whichever is longer: pedicels far thinner than
    // a pixel then take a few balls, not dozens, for at most half a pixel more reach.
    const Vec3 a = to_cam * s.start, b = to_cam * s.end;
    const double len = (b - a).norm();
    const double near = std::min(a.z(), b.z()) - s.radius;
    const double piece = std::max(2 * std::max(s.radius, 1e-9), near > 0 ? near / f : 0.0);
    const int pieces = static_cast<int>(std::clamp(std::ceil(len / piece), 1.0, 65536.0));
    const double half = 0.5 * len / pieces;
    for (int i = 0; i < pieces; ++i) {
      mark_camera_frame(a + (b - a) * ((i + 0.5) / pieces), std::sqrt(half * half + s.radius * s.radius) * (1 + 1e-9));
    }
  };
  for (const Berry& b : scene.bunch().berries) mark_camera_frame(to_cam * b.centre, b.radius * (1 + 1e-6));
  for (const Stem& s : scene.bunch().stems) mark_cylinder(s);
  const Foliage& fo = scene.foliage();
  for (const Stem& s : fo.canes) mark_cylinder(s);
  for (const auto& t : fo.triangles) {
    const Vec3& a = fo.vertices[static_cast<std::size_t>(t[0])];
    const Vec3& b = fo.vertices[static_cast<std::size_t>(t[1])];
    const Vec3& c = fo.vertices[static_cast<std::size_t>(t[2])];
    const Vec3 centroid = (a + b + c) / 3;
    const double r = std::sqrt(std::max({(a - centroid).squaredNorm(), (b - centroid).squaredNorm(),
                                         (c - centroid).squaredNorm()}));
    mark_camera_frame(to_cam * centroid, r * (1 + 1e-9) + 1e-12);
  }
  // covered[u] = rectangles over (v, u): the column sums of the row prefix sums.
  std::vector<int> covered(static_cast<std::size_t>(w), 0);
  for (int v = 0; v < h; ++v) {
    const int* row = &corners[v * stride];
    std::uint8_t* out = &mask[static_cast<std::size_t>(v) * w];
    int run = 0;
    for (int u = 0; u < w; ++u) {
      run += row[u];
      covered[u] += run;
      out[u] = covered[u] > 0;
    }
  }
  return mask;
}

OrganisedCloud frame_for(const RayScene& scene, const Camera& cam, const BunchPixels& bp) {
  OrganisedCloud out;
  const int H = cam.K.height;
  if (scene.background()) {
    out.resize(cam.K.width, H);
  } else {
    out.resize(cam.K.width, H, bp.v0, bp.visible ? bp.v1 : bp.v0);
  }
  return out;
}

std::size_t trace_row(const RayScene& scene, const Camera& cam, int v, int ua, int ub, int bu0, int bu1,
                      bool sees_bunch, std::vector<double>& uv, std::vector<Hit>& hits) {
  hits.resize(cam.K.width);
  const PixelRays ray_at = cam.pixel_rays();
  for (int u = ua; u < ub; ++u) {
    if (!(sees_bunch && u >= bu0 && u < bu1)) hits[u] = scene.background_hit(ray_at(u + 0.5, v + 0.5));
  }
  if (!sees_bunch) return 0;
  uv.resize(2 * static_cast<std::size_t>(bu1 - bu0));
  for (int u = bu0; u < bu1; ++u) {
    uv[2 * (u - bu0)] = u + 0.5;
    uv[2 * (u - bu0) + 1] = v + 0.5;
  }
  scene.intersect_image_points(ray_at, uv.data(), bu1 - bu0, hits.data() + bu0);
  return static_cast<std::size_t>(bu1 - bu0);
}

void for_rows(int height, const std::function<void(int, int)>& body) {
  const int block = 8;
  tbb::parallel_for(0, (height + block - 1) / block, [&](int b) {
    body(b * block, std::min(height, (b + 1) * block));
  });
}

}  // namespace grapebench
