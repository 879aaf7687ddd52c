// The fast path of seed 004's photogrammetry: ray-cast views of a camera pass made
// into a dense coloured cloud with a multi-view-stereo noise model instead of real
// matching. Each return moves along its camera ray by a normal error of sd
// sigma_z = z^2 sigma_d / (f b), the depth error of a point triangulated from two views
// b apart with a disparity error of sigma_d px (the rectified stereo formula,
// Z = f b / d), b being the distance to the nearest other view of the pass; a fraction
// of mismatches may take a uniform disparity error instead. The views
// are then fused on a voxel grid (one point per voxel: centroid, mean colour, majority
// label), standing in for PMVS's patches (Dey et al. 2012 used Bundler and PMVS).
#pragma once

#include <cstdint>
#include <vector>

#include "sensors/scan.h"
#include "synth/param_table.h"

namespace grapebench {

struct MvsNoiseParams {
  double disparity_sd = 0.5;  // px, sigma_d of the matching
  // Mismatches: this fraction of returns takes a disparity error drawn uniformly in
  // +-outlier_disparity px instead (depth f b / (f b / z + e)); 0 by default.
  double outlier_fraction = 0;
  double outlier_disparity = 10;  // px
};
const ParamTable<MvsNoiseParams>& mvs_noise_param_table();

struct FusionParams {
  double voxel = 0.004;  // m, edge of the fusion grid
  int min_views = 2;     // a voxel seen by fewer views is dropped (multi-view consistency)
};
const ParamTable<FusionParams>& fusion_param_table();

// One reconstructed point before fusion: world position, colour, the exact label of
// the pixel it came from, its view and its depth sd (m; 0 where unknown).
struct LabelledReturn {
  Vec3 world;
  std::array<std::uint8_t, 3> rgb;
  Part part;
  int view;
  double depth_sd;
};

struct FusedCloud {
  std::vector<Vec3> points;              // m, world
  std::vector<std::array<std::uint8_t, 3>> colours;
  std::vector<Part> labels;              // exact, the majority of the voxel's returns
  std::vector<double> depth_sd;          // m, mean sigma_z of the voxel's returns
  std::size_t returns = 0;               // returns before fusion
};

// Voxel fusion: one point per voxel seen by at least min_views views, in the order of
// the voxels' integer coordinates (deterministic). Returns labelled Background or None
// are left out.
FusedCloud fuse_returns(const std::vector<LabelledReturn>& returns, const FusionParams& p);

// The pass's views (at least two, for the baseline) through the noise model, then
// fuse_returns. Deterministic in `seed` at any thread count (each pixel's error is
// hashed from the seed, view and pixel). Throws InputError for fewer than two views or
// two views at one place. `poses` (camera to world, one per view) replaces the views'
// true poses in the back-projection when given (an SfM's or perturbed poses).
FusedCloud mvs_reconstruction(const Scan& scan, const MvsNoiseParams& p, const FusionParams& fusion,
                              std::uint64_t seed, const std::vector<Eigen::Isometry3d>& poses = {});

}  // namespace grapebench
