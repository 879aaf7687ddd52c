// Seed 001's stereo matching of single points (Luo et al. 2016, Sect. 2.2.3.1): a 9 x 9
// window about the point in the left image is searched along the same row of the right
// image over the disparities of the working depths (350-1100 mm) by zero-mean
// normalised cross-correlation (Steger et al. 2007), and accepted at a score of 0.92.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "algorithms/stereo_pair.h"
#include "synth/param_table.h"

namespace grapebench {

struct NccParams {
  int window = 9;              // px, odd (Sect. 2.2.3.1: 9 x 9)
  double min_score = 0.92;     // lowest accepted correlation (Sect. 2.2.3.1)
  double depth_min = 0.35;     // m: largest disparity searched (Sect. 2.2.3.1: 350 mm)
  double depth_max = 1.1;      // m: smallest disparity searched (1100 mm)
  double min_template_sd = 2;  // grey levels: flatter windows are not matched (their NCC is 0/0)
  bool subpixel = true;        // parabola through the peak and its neighbours (not stated)
};
const ParamTable<NccParams>& ncc_param_table();

// A single-channel 8-bit image, H x W, row-major.
struct GreyImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> data;
};
// ITU-R BT.601 luma of an RGB image (OpenCV's RGB2GRAY).
GreyImage to_grey(const RgbImage& image);

struct NccMatch {
  std::string failure;   // empty when matched: "window off the image" | "flat window" | "score below"
  double disparity = 0;  // px, x_left - x_right
  double score = 0;      // zero-mean NCC of the best disparity
  bool ok() const { return failure.empty(); }
};

// The disparity of left pixel (x, y) (rounded to the nearest pixel); fx in px,
// baseline in m set the searched disparities [fx B / depth_max, fx B / depth_min].
NccMatch ncc_disparity(const GreyImage& left, const GreyImage& right, double x, double y, double fx, double baseline,
                       const NccParams& p);

}  // namespace grapebench
