#include "sensors/visibility_hull.h"

#include "synth/config.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <string>

namespace grapebench {

namespace {

// Whether `camera` images `q` (in front of it, inside the image).
bool in_view(const Camera& camera, const Vec3& q) {
  const Vec3 c = camera.to_camera(q);
  if (!(c.z() > 0)) return false;
  const double u = camera.K.fx * c.x() / c.z() + camera.K.cx, v = camera.K.fy * c.y() / c.z() + camera.K.cy;
  return u >= 0 && v >= 0 && u < camera.K.width && v < camera.K.height;
}

}  // namespace

VisibilityHull visibility_hull(const RayScene& scene, const std::vector<Camera>& cameras, const VisibilityHullParams& p) {
  check_range(p.voxel, 1e-4, 0.05, "visibility_hull", "voxel", " m");
  check_range(p.margin, 0, 0.5, "visibility_hull", "margin", " m");
  if (cameras.empty()) throw InputError("visibility_hull: no cameras");
  const Bunch& b = scene.bunch();
  if (b.berries.empty() && b.stems.empty()) throw InputError("visibility_hull: the bunch has no berries or stems");
  Vec3 lo = scene.bunch_min(), hi = scene.bunch_max();
  lo.array() -= p.margin;
  hi.array() += p.margin;
  std::array<int, 3> n{};
  double samples = 1;
  for (int k = 0; k < 3; ++k) {
    n[static_cast<std::size_t>(k)] = std::max(1, static_cast<int>(std::ceil((hi[k] - lo[k]) / p.voxel)));
    samples *= n[static_cast<std::size_t>(k)];
  }
  if (samples > 2e8) {
    throw InputError("visibility_hull: voxel = " + std::to_string(p.voxel) + " m gives " + std::to_string(samples) +
                     " samples in the bunch's box, more than 2e8; raise voxel");
  }

  // One z slab per task; per-slab counts summed in slab order (deterministic).
  std::vector<std::size_t> hidden(static_cast<std::size_t>(n[2]), 0);
  std::vector<std::uint64_t> segments(static_cast<std::size_t>(n[2]), 0);
  tbb::parallel_for(0, n[2], [&](int z) {
    std::vector<Vec3> open;  // samples no camera has seen yet
    open.reserve(static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]));
    for (int y = 0; y < n[1]; ++y) {
      for (int x = 0; x < n[0]; ++x) open.push_back(lo + p.voxel * Vec3(x + 0.5, y + 0.5, z + 0.5));
    }
    std::vector<Vec3> from, to, still;
    std::vector<char> blocked;
    for (const Camera& camera : cameras) {
      if (open.empty()) break;
      from.clear();
      to.clear();
      still.clear();
      for (const Vec3& q : open) {
        if (in_view(camera, q)) {
          from.push_back(camera.centre());
          to.push_back(q);
        } else {
          still.push_back(q);
        }
      }
      scene.occluded(from, to, blocked);
      segments[static_cast<std::size_t>(z)] += to.size();
      for (std::size_t i = 0; i < to.size(); ++i) {
        if (blocked[i]) still.push_back(to[i]);
      }
      open.swap(still);
    }
    hidden[static_cast<std::size_t>(z)] = open.size();
  });
  VisibilityHull out;
  out.samples = static_cast<std::size_t>(samples);
  for (std::size_t z = 0; z < hidden.size(); ++z) {
    out.hidden += hidden[z];
    out.segments += segments[z];
  }
  const double cell = p.voxel * p.voxel * p.voxel;
  out.volume = static_cast<double>(out.hidden) * cell;
  out.box_volume = samples * cell;
  return out;
}

}  // namespace grapebench
