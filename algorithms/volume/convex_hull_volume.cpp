#include "algorithms/volume/convex_hull_volume.h"

#include "synth/ground_truth.h"

namespace grapebench {

VolumeEstimate convex_hull_volume(const PointCloud& cloud) {
  require_solid(cloud, "convex_hull_volume");
  std::vector<Vec3> pts(static_cast<std::size_t>(cloud.rows()));
  for (Eigen::Index i = 0; i < cloud.rows(); ++i) pts[static_cast<std::size_t>(i)] = cloud.row(i).transpose();
  HullMesh h;
  try {
    h = convex_hull(pts);
  } catch (const InputError& e) {
    throw InputError(std::string("convex_hull_volume: ") + e.what());
  }
  VolumeEstimate v;
  v.volume = h.volume;
  v.mesh_vertices = std::move(h.vertices);
  v.mesh_triangles = std::move(h.triangles);
  v.watertight = true;
  v.points_used = pts.size();
  return v;
}

}  // namespace grapebench
