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
  // Spatial correlation of the disparity error within a view: pixels k px apart along
  // a row or a column correlate by exp(-k / correlation_px); 0: independent pixels.
  // Real matching errs in patches: SGBM's errors on seed 004's rows fell off about so,
  // with a length of 7-10 px (docs/seed004.md).
  double correlation_px = 0;
  // Foreground fattening: a window matcher gives a pixel just behind a depth edge the
  // nearer surface's disparity (its block straddles the edge). A return with a surface
  // at least 3 % nearer within edge_fattening_px px (square window) takes, with
  // probability edge_fattening_fraction, the nearest depth in that window, keeping its
  // own label and colour. 0: off. SGBM on seed 004's rows: 20-26 % of such pixels off
  // by more than 3 px toward the camera (docs/seed004.md).
  int edge_fattening_px = 0;
  double edge_fattening_fraction = 1;
  // Pixel locking: sub-pixel disparities drawn toward whole pixels, an error of
  // -pixel_locking_px sin(2 pi delta), delta the fractional part of the true disparity
  // f b / z (Shimizu and Okutomi 2001: the parabola fit of integer costs). The same
  // point at the same depth gets the same error in every view, so unlike the random
  // error it survives fusion. 0: off. SGBM on a rendered slanted plane: 0.13 px
  // (tests/algorithms/stereo/sgbm_reconstruction_test.cpp; docs/seed004.md for the rows).
  double pixel_locking_px = 0;
  // The matching's baseline b in the formulas above, m; 0: the distance to the nearest
  // other view of the pass. A stereo rig's own baseline (seed004_green_sgbm: 5 cm)
  // lets the model take SGBM's figures as measured, locking's phase included.
  double baseline = 0;
  // Window smoothing: a block matcher's disparity is about the mean over its block, so
  // each return takes the mean true disparity of the surface pixels within
  // window_px px (square window; backgrounds left out), before the errors above. Small
  // curved parts flatten and are drawn toward what lies behind them. 0: off. SGBM's
  // block is 5 px (window_px 2); its berry and branch disparities averaged 0.2-0.4 px
  // too far on seed 004's rows (summary.json's disparity_bias).
  int window_px = 0;
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

// Per pixel of a width x height view (row-major), a standard normal error: with
// correlation_px = 0 the hashed draws hashed_normal(seed, i); otherwise those draws
// passed through a stationary AR(1) recursion along each row and then each column,
// so every value keeps unit variance and values dx, dy px apart correlate by
// exp(-(|dx| + |dy|) / correlation_px).
std::vector<double> correlated_normal_field(int width, int height, double correlation_px, std::uint64_t seed);

// Per pixel of a view (row-major), the smallest true depth (m) within r px, square
// window, among the pixels that see a surface (infinity where none does); empty when
// r = 0. A pixel lies just behind a depth edge where that depth is below
// kBehindEdgeDepthRatio times its own (a surface at least 3 % nearer).
std::vector<float> nearest_depth_within(const OrganisedCloud& c, int r);
inline constexpr double kBehindEdgeDepthRatio = 0.97;

// Per pixel of a view (row-major), the depth (m) of the mean disparity of the pixels
// within r px (square window) that see a surface other than the background: the
// harmonic mean of their true depths; infinity where none does; empty when r = 0.
std::vector<float> window_mean_depth(const OrganisedCloud& c, int r);

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
