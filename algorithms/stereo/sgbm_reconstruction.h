// Dense matching of a rectified colour pair for seed 004's photogrammetry (the
// stand-in for PMVS, Dey et al. 2012 Sect. 3.1): OpenCV's semi-global block matching
// (Hirschmueller 2008) for the left and the right image, a left-right consistency
// check, and back-projection with the left image's colours (Z = f b / d).
#pragma once

#include <cstdint>
#include <vector>

#include "algorithms/point_cloud.h"
#include "algorithms/stereo_pair.h"
#include "synth/param_table.h"

namespace grapebench {

struct SgbmParams {
  double min_depth = 0.4, max_depth = 3.0;  // m: the disparity range searched
  int block_size = 5;                       // px, odd
  // Smoothness penalties per OpenCV's recommendation: P1 = p1 * 3 * block^2,
  // P2 = p2 * 3 * block^2 (3 channels).
  double p1 = 8, p2 = 32;
  int uniqueness = 10;           // %, margin of the best cost over the second
  int speckle_window = 100;      // px; 0 switches the speckle filter off
  int speckle_range = 2;         // px of disparity within a speckle
  double lr_tolerance = 1.0;     // px: left and right disparities must agree this well
};
const ParamTable<SgbmParams>& sgbm_param_table();

struct SgbmCloud {
  PointCloud points;                 // M x 3, m, the left camera's frame (x right, y down, z forward)
  std::vector<Rgb8> colours;         // M, the left image's pixel
  std::vector<std::uint32_t> pixel;  // M, y * width + x of the left image
  int matched = 0;                   // pixels with a disparity before the left-right check
  int consistent = 0;                // after it (= M)
};

// Throws InputError when the images differ in size or are empty, or the camera or the
// depth range is degenerate.
SgbmCloud sgbm_reconstruction(const StereoPair& pair, const SgbmParams& p);

}  // namespace grapebench
