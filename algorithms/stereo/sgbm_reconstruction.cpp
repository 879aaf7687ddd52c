#include "algorithms/stereo/sgbm_reconstruction.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace grapebench {

const ParamTable<SgbmParams>& sgbm_param_table() {
  using P = SgbmParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("min_depth", "m", &P::min_depth, 0.05, 100, "nearest depth searched (largest disparity)")
          .real("max_depth", "m", &P::max_depth, 0.05, 1000, "farthest depth searched (smallest disparity)")
          .integer("block_size", "px", &P::block_size, 1, 31, "matching block, odd (OpenCV StereoSGBM)")
          .real("p1", "-", &P::p1, 0, 1000, "P1 = p1 * 3 * block^2: penalty of a 1 px disparity change")
          .real("p2", "-", &P::p2, 0, 1000, "P2 = p2 * 3 * block^2: penalty of a larger change (above p1)")
          .integer("uniqueness", "%", &P::uniqueness, 0, 100, "margin of the best cost over the second best")
          .integer("speckle_window", "px", &P::speckle_window, 0, 10000, "speckle filter window; 0 off")
          .integer("speckle_range", "px", &P::speckle_range, 0, 64, "disparity spread within a speckle")
          .real("lr_tolerance", "px", &P::lr_tolerance, 0, 10, "left-right consistency: disparities agree this well")
          .validate([](const P& p, const ConfigNode& n) {
            if (p.block_size % 2 == 0) n.fail("block_size", "must be odd");
            if (p.min_depth >= p.max_depth) n.fail("min_depth", "must be below max_depth");
            if (p.p2 <= p.p1) n.fail("p2", "must exceed p1");
          });
  return table;
}

namespace {

// The image as an OpenCV matrix (a copy; SGBM treats the three channels alike, so
// their order does not matter).
cv::Mat mat_of(const RgbImage& im) {
  return cv::Mat(im.height, im.width, CV_8UC3, const_cast<std::uint8_t*>(im.data.data())).clone();
}

// Disparity in px (CV_32F; below min_disp: no match) of `a` against `b`.
cv::Mat disparity(const cv::Mat& a, const cv::Mat& b, int min_disp, int num_disp, const SgbmParams& p) {
  const int area = 3 * p.block_size * p.block_size;
  cv::Ptr<cv::StereoSGBM> sgbm = cv::StereoSGBM::create(
      min_disp, num_disp, p.block_size, static_cast<int>(p.p1 * area), static_cast<int>(p.p2 * area), 1,
      0, p.uniqueness, p.speckle_window, p.speckle_range, cv::StereoSGBM::MODE_SGBM);
  cv::Mat fixed, out;
  sgbm->compute(a, b, fixed);
  fixed.convertTo(out, CV_32F, 1.0 / 16);  // StereoSGBM's 4 fractional bits
  return out;
}

}  // namespace

SgbmCloud sgbm_reconstruction(const StereoPair& pair, const SgbmParams& p) {
  const RgbImage &l = pair.left, &r = pair.right;
  if (l.width <= 0 || l.height <= 0 || l.width != r.width || l.height != r.height ||
      l.data.size() != static_cast<std::size_t>(l.width) * l.height * 3 || r.data.size() != l.data.size())
    throw InputError("sgbm_reconstruction: the images are empty, differ in size or are not W x H x 3");
  if (!(pair.fx > 0) || !(pair.baseline > 0) || !(p.min_depth < p.max_depth))
    throw InputError("sgbm_reconstruction: focal length, baseline and depth range must be positive");
  const double fb = pair.fx * pair.baseline;
  const int min_disp = std::max(0, static_cast<int>(std::floor(fb / p.max_depth)));
  int num_disp = static_cast<int>(std::ceil(fb / p.min_depth)) - min_disp + 1;
  num_disp = std::max(16, (num_disp + 15) / 16 * 16);  // OpenCV: a multiple of 16
  if (min_disp + num_disp >= l.width) throw InputError("sgbm_reconstruction: the disparity range exceeds the image");
  const cv::Mat left = mat_of(l), right = mat_of(r);
  const cv::Mat dl = disparity(left, right, min_disp, num_disp, p);
  // The right image's disparities: both images mirrored and swapped.
  cv::Mat lf, rf, drf, dr;
  cv::flip(left, lf, 1);
  cv::flip(right, rf, 1);
  drf = disparity(rf, lf, min_disp, num_disp, p);
  cv::flip(drf, dr, 1);

  SgbmCloud out;
  std::vector<Vec3> pts;
  for (int y = 0; y < l.height; ++y) {
    for (int x = 0; x < l.width; ++x) {
      const float d = dl.at<float>(y, x);
      if (!(d >= min_disp)) continue;
      ++out.matched;
      const int xr = static_cast<int>(std::lround(x - d));
      if (xr < 0 || xr >= l.width) continue;
      const float d2 = dr.at<float>(y, xr);
      if (!(d2 >= min_disp) || std::abs(d2 - d) > p.lr_tolerance) continue;
      const double z = fb / d;
      pts.emplace_back((x - pair.cx) * z / pair.fx, (y - pair.cy) * z / pair.fy, z);
      const std::uint8_t* c = l.pixel(x, y);
      out.colours.push_back({c[0], c[1], c[2]});
      out.pixel.push_back(static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(l.width) +
                          static_cast<std::uint32_t>(x));
    }
  }
  out.consistent = static_cast<int>(pts.size());
  out.points = to_point_cloud(pts);
  return out;
}

}  // namespace grapebench
