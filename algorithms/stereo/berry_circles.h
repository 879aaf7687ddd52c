// Seed 001's berry detection (Luo et al. 2016, Sect. 2.2.2.4): gradient Hough circles
// in the cluster's bounding rectangle with the accumulator threshold 13, a least-squares
// refit of each circle to its edge points, the radius window predicted from the depth
// (Eq. 6, or the pinhole model) and the three rules of Eq. 7.
#pragma once

#include <vector>

#include "algorithms/segmentation/cluster_segmentation.h"
#include "algorithms/estimate.h"

namespace grapebench {

struct BerryCircleParams {
  double berry_radius_min = 0.008;  // m, r_t of the smallest berry (Sect. 2.2.2.4: 8 mm)
  double berry_radius_max = 0.020;  // m, r_t of the largest berry (Sect. 2.2.2.4: 20 mm)
  // eq6: r = 3185 r_t z^-1.16 (r_t, z in mm; fitted to the paper's camera). pinhole:
  // r = f r_t / z with this camera's f.
  enum class RadiusModel { Eq6, Pinhole };
  RadiusModel radius_model = RadiusModel::Eq6;
  double accumulator_votes = 13;  // HoughCircles' param2 (Sect. 2.2.2.4: 13)
  // Not stated in the paper; chosen on the analytic pair of tests/algorithms/
  // luo2016_stereo_test.cpp (sigma 1.5 with 100 lost the edges between touching berries).
  double canny_high = 60;     // HoughCircles' param1: its Canny high threshold
  double blur_sigma = 1.0;    // px, Gaussian smoothing before the edges (the paper's "filter")
  double refit_band = 2;      // px: edge points within this of a circle refit it
  int min_refit_points = 12;  // fewer edge points keep the Hough circle
};
const ParamTable<BerryCircleParams>& berry_circle_param_table();

// The radius window in pixels at depth z (m) from the chosen model.
struct RadiusWindow {
  double r_min = 0, r_max = 0;  // px
};
RadiusWindow berry_radius_window(const BerryCircleParams& p, double depth, double fx);

// Kasa's least-squares circle through points (x, y), px; nullopt for fewer than three
// or collinear points.
std::optional<Circle> fit_circle(const std::vector<double>& x, const std::vector<double>& y);

struct BerryCircles {
  std::vector<Detection> berries;  // kept circles, px; score: Hough votes
  RadiusWindow window;
  int candidates = 0;  // circles before Eq. 7's rules
  int refitted = 0;    // circles moved by the least-squares refit
};

// Circles of the cluster at depth `depth` (m, from the camera) in the region's
// bounding rectangle; fx in pixels.
BerryCircles detect_berries(const RgbImage& image, const ClusterRegion& region, double depth, double fx,
                            const BerryCircleParams& p);

}  // namespace grapebench
