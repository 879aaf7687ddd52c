#include "algorithms/stereo/cutting_point_detection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

namespace grapebench {

double line_distance(const LineSegment& s, double x, double y) {
  const double dx = s.x2 - s.x1, dy = s.y2 - s.y1;
  const double len = std::hypot(dx, dy);
  if (len <= 0) return std::hypot(x - s.x1, y - s.y1);
  // Eq. 4: |(x - x1)(y2 - y1) + (y - y1)(x1 - x2)| / sqrt((y2 - y1)^2 + (x1 - x2)^2).
  return std::abs((x - s.x1) * dy - (y - s.y1) * dx) / len;
}

std::vector<LineSegment> hough_line_segments(const std::vector<std::uint8_t>& grey, int width, int height,
                                             const CuttingPointParams& p) {
  const cv::Mat src(height, width, CV_8U, const_cast<std::uint8_t*>(grey.data()));
  cv::Mat smooth, edges;
  cv::bilateralFilter(src, smooth, p.bilateral_diameter, p.bilateral_sigma_colour, p.bilateral_sigma_space);
  cv::Canny(smooth, edges, p.canny_low, p.canny_high);
  std::vector<cv::Vec4i> lines;
  cv::HoughLinesP(edges, lines, 1, CV_PI / 180, p.hough_votes, p.min_line_length, p.max_line_gap);
  std::vector<LineSegment> out;
  for (const auto& l : lines) out.push_back({double(l[0]), double(l[1]), double(l[2]), double(l[3])});
  return out;
}

CuttingPointDetection detect_cutting_point(const RgbImage& image, const ClusterRegion& region,
                                           const CuttingPointParams& p) {
  CuttingPointDetection d;
  // Eq. 2: Roi_L = 0.8 L_max, Roi_H = 0.5 |y_c - y_t|, centred on (x_c, y_t - Roi_H / 2).
  const double roi_l = p.roi_length_factor * region.l_max;
  const double roi_h = p.roi_height_factor * std::abs(region.yc - region.yt);
  const int x0 = std::max(0, static_cast<int>(std::floor(region.xc - 0.5 * roi_l)));
  const int x1 = std::min(image.width, static_cast<int>(std::ceil(region.xc + 0.5 * roi_l)));
  const int y0 = std::max(0, static_cast<int>(std::floor(region.yt - roi_h)));
  const int y1 = std::min(image.height, static_cast<int>(std::ceil(region.yt)));
  d.roi_x = x0, d.roi_y = y0, d.roi_width = std::max(0, x1 - x0), d.roi_height = std::max(0, y1 - y0);
  if (d.roi_width < 3 || d.roi_height < 3) {
    d.failure = "the peduncle ROI is empty (the cluster touches the image top)";
    return d;
  }
  std::vector<std::uint8_t> grey(static_cast<std::size_t>(d.roi_width) * d.roi_height);
  for (int y = 0; y < d.roi_height; ++y) {
    for (int x = 0; x < d.roi_width; ++x) {
      const std::uint8_t* px = image.pixel(x0 + x, y0 + y);
      grey[static_cast<std::size_t>(y) * d.roi_width + x] =
          static_cast<std::uint8_t>((299 * px[0] + 587 * px[1] + 114 * px[2] + 500) / 1000);
    }
  }
  d.lines = hough_line_segments(grey, d.roi_width, d.roi_height, p);
  if (d.lines.empty()) {
    d.failure = "no line in the peduncle ROI";
    return d;
  }
  d.distance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < d.lines.size(); ++i) {
    LineSegment& s = d.lines[i];
    s.x1 += x0, s.x2 += x0, s.y1 += y0, s.y2 += y0;
    const double dist = line_distance(s, region.xc, region.yc);
    if (dist < d.distance) d.distance = dist, d.chosen = static_cast<int>(i);
  }
  const LineSegment& best = d.lines[static_cast<std::size_t>(d.chosen)];
  d.x = 0.5 * (best.x1 + best.x2);
  d.y = 0.5 * (best.y1 + best.y2);
  return d;
}

const ParamTable<CuttingPointParams>& cutting_point_param_table() {
  using P = CuttingPointParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("roi_length_factor", "-", &P::roi_length_factor, 0.05, 5,
                "Roi_L = factor x L_max (seed 001 Eq. 2: 0.8)")
          .real("roi_height_factor", "-", &P::roi_height_factor, 0.05, 5,
                "Roi_H = factor x |y_c - y_t| (seed 001 Eq. 2: 0.5)")
          .integer("bilateral_diameter", "px", &P::bilateral_diameter, 1, 31, "bilateral filter diameter (seed 001: 7)")
          .real("bilateral_sigma_colour", "grey", &P::bilateral_sigma_colour, 0.1, 255,
                "bilateral filter colour sigma (seed 001: 20)")
          .real("bilateral_sigma_space", "px", &P::bilateral_sigma_space, 0.1, 50,
                "bilateral filter space sigma (seed 001: 4)")
          .real("canny_low", "grey", &P::canny_low, 0, 1000, "Canny hysteresis low threshold (not stated in seed 001)")
          .real("canny_high", "grey", &P::canny_high, 0, 1000,
                "Canny hysteresis high threshold (not stated in seed 001)")
          .integer("hough_votes", "votes", &P::hough_votes, 1, 10000,
                   "probabilistic Hough accumulator threshold (seed 001: 16)")
          .real("min_line_length", "px", &P::min_line_length, 1, 10000, "shortest line kept (seed 001: 20 px)")
          .real("max_line_gap", "px", &P::max_line_gap, 0, 1000,
                "largest gap joined within a line (not stated in seed 001)")
          .validate([](const P& p, const ConfigNode& n) {
            if (p.canny_low > p.canny_high) n.fail("canny_low", "must not exceed canny_high");
          });
  return table;
}

}  // namespace grapebench
