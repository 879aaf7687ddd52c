#include "algorithms/volume/voxel_volume.h"

#include <cmath>
#include <vector>

namespace grapebench {

VolumeEstimate voxel_volume(const PointCloud& cloud, const VoxelVolumeParams& p) {
  require_solid(cloud, "voxel_volume");
  if (!(p.voxel_size >= 1e-4 && p.voxel_size <= 0.5)) {
    throw InputError("voxel_volume: voxel_size " + std::to_string(p.voxel_size) + " m is outside [0.0001, 0.5]");
  }
  const double k = p.voxel_size;
  const Eigen::RowVector3d lo = cloud.colwise().minCoeff(), hi = cloud.colwise().maxCoeff();
  // One empty voxel of padding on every side so the exterior is connected.
  long n[3];
  double cells = 1;
  for (int a = 0; a < 3; ++a) {
    n[a] = static_cast<long>(std::floor((hi[a] - lo[a]) / k)) + 3;
    cells *= static_cast<double>(n[a]);
  }
  if (cells > p.max_cells) {
    throw InputError("voxel_volume: " + std::to_string(static_cast<long long>(cells)) +
                     " cells exceed max_cells; use a larger voxel_size");
  }
  const auto at = [&](long x, long y, long z) { return static_cast<std::size_t>((z * n[1] + y) * n[0] + x); };
  std::vector<std::uint8_t> grid(static_cast<std::size_t>(cells), 0);  // 1 occupied, 2 exterior
  for (Eigen::Index i = 0; i < cloud.rows(); ++i) {
    long c[3];
    for (int a = 0; a < 3; ++a) c[a] = static_cast<long>(std::floor((cloud(i, a) - lo[a]) / k)) + 1;
    grid[at(c[0], c[1], c[2])] = 1;
  }
  std::size_t occupied = 0;
  for (auto g : grid) occupied += g == 1;
  std::size_t counted = occupied;
  if (p.fill_interior) {
    std::vector<std::size_t> stack{at(0, 0, 0)};
    grid[stack.back()] = 2;
    std::size_t exterior = 1;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      const long x = static_cast<long>(i % n[0]), y = static_cast<long>((i / n[0]) % n[1]),
                 z = static_cast<long>(i / (n[0] * n[1]));
      const long nb[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z}, {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= n[0] || q[1] >= n[1] || q[2] >= n[2]) continue;
        const std::size_t j = at(q[0], q[1], q[2]);
        if (grid[j] != 0) continue;
        grid[j] = 2;
        ++exterior;
        stack.push_back(j);
      }
    }
    counted = static_cast<std::size_t>(cells) - exterior;
  }
  VolumeEstimate v;
  // With fill_interior, the shell enclosed something only if the fill could not
  // reach every empty voxel; voxels finer than the point spacing leave holes.
  v.watertight = p.fill_interior && counted > occupied;
  v.volume = static_cast<double>(counted) * k * k * k;  // seed 000, Eq. 7
  v.points_used = static_cast<std::size_t>(cloud.rows());
  v.notes = std::to_string(occupied) + " occupied voxels, " + std::to_string(counted) + " counted, edge " +
            std::to_string(k) + " m";
  if (p.fill_interior && !v.watertight) v.notes += "; the voxel shell is not closed (voxel finer than the point spacing?): nothing filled";
  return v;
}

const ParamTable<VoxelVolumeParams>& voxel_volume_param_table() {
  using P = VoxelVolumeParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("voxel_size", "m", &P::voxel_size, 1e-4, 0.5, "voxel edge k (seed 000 Eq. 7 states 0.2 m)")
          .boolean("fill_interior", &P::fill_interior, "count the voxels the occupied shell encloses too")
          .real("max_cells", "count", &P::max_cells, 1e3, 1e9, "refuse larger grids");
  return table;
}

}  // namespace grapebench
