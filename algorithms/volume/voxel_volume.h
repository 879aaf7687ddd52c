// VB: voxel-based volume of seed 000 (Eq. 7). Written here rather than with PCL's
// VoxelGrid: that returns voxel centroids only (no interior fill) and overflows its
// integer voxel indices on fine grids.
#pragma once

#include "algorithms/point_cloud.h"
#include "synth/param_table.h"
#include "algorithms/volume_estimate.h"

namespace grapebench {

struct VoxelVolumeParams {
  // Voxel edge k, m, range [1e-4, 0.5]. Seed 000 states "0.2 m", which cannot be meant
  // (the whole bunch is about 0.2 m); 10 mm is the default and the edge is swept.
  double voxel_size = 0.01;
  // Count the voxels enclosed by the occupied shell too (the paper's stacked-cube
  // model of the bunch); false counts only voxels that contain points.
  bool fill_interior = true;
  // Refuse grids larger than this many cells, [1e3, 1e9].
  double max_cells = 2e8;
};
const ParamTable<VoxelVolumeParams>& voxel_volume_param_table();

// Eq. 7: V = sum over counted voxels of k^3. The grid is aligned with the cloud's
// minimum corner; with fill_interior the exterior is flood-filled from the grid's
// padded border (6-connected) and every voxel it cannot reach counts. `watertight`
// in the result says whether the shell enclosed anything.
VolumeEstimate voxel_volume(const PointCloud& cloud, const VoxelVolumeParams& params = {});

}  // namespace grapebench
