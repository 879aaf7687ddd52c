#include "algorithms/stereo/ncc_disparity.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace grapebench {

GreyImage to_grey(const RgbImage& image) {
  GreyImage g{image.width, image.height,
              std::vector<std::uint8_t>(static_cast<std::size_t>(image.width) * image.height)};
  const cv::Mat src(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.data.data()));
  cv::Mat dst(image.height, image.width, CV_8U, g.data.data());
  cv::cvtColor(src, dst, cv::COLOR_RGB2GRAY);
  return g;
}

NccMatch ncc_disparity(const GreyImage& left, const GreyImage& right, double x, double y, double fx, double baseline,
                       const NccParams& p) {
  NccMatch m;
  const int h = p.window / 2;
  const int u = static_cast<int>(std::lround(x)), v = static_cast<int>(std::lround(y));
  const int d_lo = static_cast<int>(std::floor(fx * baseline / p.depth_max));
  const int d_hi = static_cast<int>(std::ceil(fx * baseline / p.depth_min));
  // The right image's columns that the searched windows cover, clipped to the image.
  const int r0 = std::max(h, u - d_hi), r1 = std::min(right.width - 1 - h, u - d_lo);
  if (u - h < 0 || v - h < 0 || u + h >= left.width || v + h >= left.height || r0 > r1) {
    m.failure = "the matching window leaves the image";
    return m;
  }
  const cv::Mat L(left.height, left.width, CV_8U, const_cast<std::uint8_t*>(left.data.data()));
  const cv::Mat R(right.height, right.width, CV_8U, const_cast<std::uint8_t*>(right.data.data()));
  const cv::Mat templ = L(cv::Rect(u - h, v - h, p.window, p.window));
  cv::Scalar mean, sd;
  cv::meanStdDev(templ, mean, sd);
  if (sd[0] < p.min_template_sd) {
    m.failure = "flat matching window (sd " + std::to_string(sd[0]) + " grey levels)";
    return m;
  }
  const cv::Mat strip = R(cv::Rect(r0 - h, v - h, r1 - r0 + p.window, p.window));
  cv::Mat score;
  cv::matchTemplate(strip, templ, score, cv::TM_CCOEFF_NORMED);  // 1 x (r1 - r0 + 1)
  cv::Point best;
  double best_score = 0;
  cv::minMaxLoc(score, nullptr, &best_score, nullptr, &best);
  m.score = best_score;
  double xr = r0 + best.x;
  if (p.subpixel && best.x > 0 && best.x + 1 < score.cols) {
    const double a = score.at<float>(0, best.x - 1), b = score.at<float>(0, best.x), c = score.at<float>(0, best.x + 1);
    const double den = a - 2 * b + c;
    if (den < 0) xr += 0.5 * (a - c) / den;
  }
  m.disparity = u - xr;
  if (!(best_score >= p.min_score)) {
    m.failure = "correlation " + std::to_string(best_score) + " below the accepted " + std::to_string(p.min_score);
  }
  return m;
}

const ParamTable<NccParams>& ncc_param_table() {
  using P = NccParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .integer("window", "px", &P::window, 3, 63, "side of the square matching window, odd (seed 001: 9)")
          .real("min_score", "-", &P::min_score, -1, 1, "lowest accepted zero-mean NCC (seed 001: 0.92)")
          .real("depth_min", "m", &P::depth_min, 0.05, 100, "nearest depth searched (seed 001: 350 mm)")
          .real("depth_max", "m", &P::depth_max, 0.05, 100, "farthest depth searched (seed 001: 1100 mm)")
          .real("min_template_sd", "grey", &P::min_template_sd, 0, 128,
                "windows with a smaller grey-level sd are not matched (their zero-mean NCC is undefined)")
          .boolean("subpixel", &P::subpixel, "refine the disparity by a parabola through the peak (not stated)")
          .validate([](const P& p, const ConfigNode& n) {
            if (p.window % 2 == 0) n.fail("window", "must be odd");
            if (p.depth_min >= p.depth_max) n.fail("depth_min", "must be below depth_max");
          });
  return table;
}

}  // namespace grapebench
