// Seed 001's cutting point on the peduncle (Luo et al. 2016, Sect. 2.2.2.3): the
// peduncle ROI above the cluster (Eq. 2), a bilateral filter, Canny edges and
// progressive probabilistic Hough lines; the line nearest the barycentre (Eq. 4) and its
// midpoint.
#pragma once

#include <string>
#include <vector>

#include "algorithms/segmentation/cluster_segmentation.h"

namespace grapebench {

struct CuttingPointParams {
  double roi_length_factor = 0.8;  // Roi_L = 0.8 L_max (Eq. 2)
  double roi_height_factor = 0.5;  // Roi_H = 0.5 |y_c - y_t| (Eq. 2)
  int bilateral_diameter = 7;      // px (Sect. 2.2.2.3: bilateral filter 7, 20, 4)
  double bilateral_sigma_colour = 20;
  double bilateral_sigma_space = 4;
  double canny_low = 30, canny_high = 90;  // grey levels (not stated)
  int hough_votes = 16;                    // accumulator threshold (Sect. 2.2.2.3)
  double min_line_length = 20;             // px (Sect. 2.2.2.3)
  double max_line_gap = 5;                 // px (not stated)
};
const ParamTable<CuttingPointParams>& cutting_point_param_table();

// A line segment in image pixels.
struct LineSegment {
  double x1 = 0, y1 = 0, x2 = 0, y2 = 0;
};

struct CuttingPointDetection {
  std::string failure;  // empty when found: "the peduncle ROI is empty" | "no line in the peduncle ROI"
  int roi_x = 0, roi_y = 0, roi_width = 0, roi_height = 0;  // the ROI, clipped to the image, px
  std::vector<LineSegment> lines;                           // Hough lines in image pixels
  int chosen = -1;                                          // index of the line nearest the barycentre
  double distance = 0;                                      // its distance to the barycentre, px (Eq. 4)
  double x = 0, y = 0;                                      // the cutting point: the chosen line's midpoint, px
  bool found() const { return failure.empty(); }
};

// Distance of (x, y) from the infinite line through a segment's end points (Eq. 4).
double line_distance(const LineSegment& s, double x, double y);

// The Hough lines of a grey image region (bilateral filter, Canny, HoughLinesP), in the
// region's pixels; what the cutting point detector runs on its ROI.
std::vector<LineSegment> hough_line_segments(const std::vector<std::uint8_t>& grey, int width, int height,
                                             const CuttingPointParams& p);

CuttingPointDetection detect_cutting_point(const RgbImage& image, const ClusterRegion& region,
                                           const CuttingPointParams& p);

}  // namespace grapebench
