#include "algorithms/segmentation/cluster_segmentation.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace grapebench {

namespace {

// H of HSI in [0, 1] (Gonzalez & Woods): theta = acos(((R-G) + (R-B)) / 2 /
// sqrt((R-G)^2 + (R-B)(G-B))), H = theta, or 360 deg - theta when B > G; grey is 0.
double hsi_hue(double r, double g, double b) {
  const double num = 0.5 * ((r - g) + (r - b));
  const double den = std::sqrt((r - g) * (r - g) + (r - b) * (g - b));
  if (den <= 1e-12) return 0;
  const double theta = std::acos(std::clamp(num / den, -1.0, 1.0));
  return (b > g ? 2 * M_PI - theta : theta) / (2 * M_PI);
}

// The H - I level of one pixel, 0-255: lround((H - I + 1) 127.5), I = (R + G + B) / 3
// of the 0-1 channels (H - I in [-1, 1]).
std::uint8_t hue_minus_intensity(std::uint8_t R, std::uint8_t G, std::uint8_t B) {
  const double r = R / 255.0, g = G / 255.0, b = B / 255.0;
  const double hi = hsi_hue(r, g, b) - (r + g + b) / 3.0;
  return static_cast<std::uint8_t>(std::lround((hi + 1.0) * 127.5));
}

// The same level's real value (before rounding) within 1e-6 (r, g, b: the 0-1
// channels): acos within 2e-8 rad (Abramowitz & Stegun 4.4.46, with acos(-x) =
// pi - acos(x)) moves it by at most 127.5 x 2e-8 / (2 pi) < 5e-7. std::acos and its
// rounding were a third of Luo's pipeline on a `ray` pair (docs/seed001.md, "Speed").
double hue_minus_intensity_approx(double r, double g, double b) {
  const double num = 0.5 * ((r - g) + (r - b));
  const double d2 = (r - g) * (r - g) + (r - b) * (g - b);
  const double den = std::sqrt(d2 > 0 ? d2 : 0.0);
  const bool grey = den <= 1e-12;
  const double q = num / (grey ? 1.0 : den), lo = q < -1.0 ? -1.0 : q, x = lo > 1.0 ? 1.0 : lo;
  const double a = x < 0 ? -x : x;
  const double poly =
      1.5707963050 +
      a * (-0.2145988016 +
           a * (0.0889789874 +
                a * (-0.0501743046 + a * (0.0308918810 + a * (-0.0170881256 + a * (0.0066700901 - a * 0.0012624911))))));
  const double t = std::sqrt(1 - a) * poly, theta = x < 0 ? M_PI - t : t;
  const double h = grey ? 0.0 : (b > g ? 2 * M_PI - theta : theta) * (1 / (2 * M_PI));
  return (h - (r + g + b) / 3.0 + 1.0) * 127.5;
}

cv::Mat dilation_kernel(const ClusterSegmentationParams& p) {
  return cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * p.dilate_px + 1, 2 * p.dilate_px + 1));
}

cv::Mat as_mat(const RgbImage& image) {
  return cv::Mat(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.data.data()));
}

// Holes: background pixels not reachable from the border, set.
void fill_holes(const cv::Mat& binary, cv::Mat& region) {
  cv::Mat outside = cv::Mat::zeros(binary.rows + 2, binary.cols + 2, CV_8U);
  region.copyTo(outside(cv::Rect(1, 1, binary.cols, binary.rows)));
  cv::floodFill(outside, cv::Point(0, 0), 128);
  const cv::Mat inner = outside(cv::Rect(1, 1, binary.cols, binary.rows));
  region.setTo(255, inner == 0);
}

// The largest connected region of at least `min_px` pixels (8-connected), holes filled.
cv::Mat largest_region(const cv::Mat& binary, int min_px) {
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(binary, labels, stats, centroids, 8, CV_32S);
  int best = -1, best_area = 0;
  for (int k = 1; k < n; ++k) {
    const int a = stats.at<int>(k, cv::CC_STAT_AREA);
    if (a >= min_px && a > best_area) best = k, best_area = a;
  }
  cv::Mat region = cv::Mat::zeros(binary.size(), CV_8U);
  if (best < 0) return region;
  region.setTo(255, labels == best);
  fill_holes(binary, region);
  return region;
}

// Otsu's binary image of the component, dilated; empty when the component is flat.
cv::Mat cluster_binary(const RgbImage& image, const ClusterSegmentationParams& p, double& threshold) {
  std::vector<std::uint8_t> component = cluster_component(image, p.component);
  const cv::Mat comp(image.height, image.width, CV_8U, component.data());
  double lo = 0, hi = 0;
  cv::minMaxLoc(comp, &lo, &hi);
  if (hi - lo < 8) return {};  // a flat component has no two classes for Otsu to split
  cv::Mat binary;
  threshold = cv::threshold(comp, binary, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  cv::dilate(binary, binary, dilation_kernel(p));
  return binary;
}

// The region's geometry (Eqs. 1-2) from its mask; area 0 below min_cluster_px.
void region_geometry(const cv::Mat& region, const ClusterSegmentationParams& p, ClusterRegion& r) {
  r.mask.assign(region.datastart, region.dataend);
  double sx = 0, sy = 0;
  r.x0 = r.width, r.y0 = r.height, r.x1 = -1, r.y1 = -1;
  for (int y = 0; y < r.height; ++y) {
    for (int x = 0; x < r.width; ++x) {
      if (!r.mask[static_cast<std::size_t>(y) * r.width + x]) continue;
      ++r.area;
      sx += x, sy += y;
      r.x0 = std::min(r.x0, x), r.x1 = std::max(r.x1, x), r.y0 = std::min(r.y0, y), r.y1 = std::max(r.y1, y);
    }
  }
  if (r.area < p.min_cluster_px) {
    r.area = 0;
    return;
  }
  r.xc = sx / r.area;
  r.yc = sy / r.area;
  // Top point: the middle of the region's pixels in its top row.
  int first = -1, last = -1;
  for (int x = 0; x < r.width; ++x) {
    if (!r.mask[static_cast<std::size_t>(r.y0) * r.width + x]) continue;
    if (first < 0) first = x;
    last = x;
  }
  r.xt = 0.5 * (first + last);
  r.yt = r.y0;
  r.l_max = r.x1 - r.x0;
}

}  // namespace

std::vector<std::uint8_t> cluster_component(const RgbImage& image, ClusterSegmentationParams::Component c) {
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  std::vector<std::uint8_t> out(n);
  if (c == ClusterSegmentationParams::Component::Cr) {
    cv::Mat ycrcb;
    cv::cvtColor(as_mat(image), ycrcb, cv::COLOR_RGB2YCrCb);  // Cr is channel 1
    for (std::size_t i = 0; i < n; ++i) out[i] = ycrcb.data[3 * i + 1];
    return out;
  }
  // The approximate value; within 1e-5 of a half (ties included: a grey pixel's value
  // can be one) the exact formula rounds. The same bytes as the exact formula for all
  // 2^24 colours (tests/algorithms/segmentation).
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* rgb = image.data.data() + 3 * i;
    const double y = hue_minus_intensity_approx(rgb[0] / 255.0, rgb[1] / 255.0, rgb[2] / 255.0) + 0.5;
    const int q = static_cast<int>(y);  // y > 0: its floor
    const double f = y - q;
    out[i] = f > 1e-5 && f < 1 - 1e-5 ? static_cast<std::uint8_t>(q) : hue_minus_intensity(rgb[0], rgb[1], rgb[2]);
  }
  return out;
}

ClusterRegion segment_cluster(const RgbImage& image, const ClusterSegmentationParams& p) {
  ClusterRegion r;
  r.width = image.width;
  r.height = image.height;
  const cv::Mat binary = cluster_binary(image, p, r.otsu_threshold);
  if (binary.empty()) return r;
  cv::Mat region = largest_region(binary, std::max(p.min_region_px, p.min_cluster_px));
  cv::dilate(region, region, dilation_kernel(p));
  region_geometry(region, p, r);
  return r;
}

ClusterRegion cluster_region_of_mask(const std::vector<std::uint8_t>& mask, int width, int height,
                                     const ClusterSegmentationParams& p) {
  if (width <= 0 || height <= 0 || mask.size() != static_cast<std::size_t>(width) * height)
    throw InputError("cluster region: a mask of " + std::to_string(mask.size()) + " values for a " +
                     std::to_string(width) + " x " + std::to_string(height) + " image");
  ClusterRegion r;
  r.width = width, r.height = height;
  cv::Mat region(height, width, CV_8U);
  for (std::size_t i = 0; i < mask.size(); ++i) region.data[i] = mask[i] ? 255 : 0;
  fill_holes(region, region);  // its first argument gives only the size
  region_geometry(region, p, r);
  return r;
}

std::vector<ClusterRegion> segment_clusters(const RgbImage& image, const ClusterSegmentationParams& p) {
  std::vector<ClusterRegion> out;
  double threshold = 0;
  const cv::Mat binary = cluster_binary(image, p, threshold);
  if (binary.empty()) return out;
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(binary, labels, stats, centroids, 8, CV_32S);
  std::vector<std::pair<int, int>> kept;  // (area, label), largest first
  for (int k = 1; k < n; ++k) {
    const int a = stats.at<int>(k, cv::CC_STAT_AREA);
    if (a >= std::max(p.min_region_px, p.min_cluster_px)) kept.emplace_back(a, k);
  }
  std::stable_sort(kept.begin(), kept.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  for (const auto& [area, k] : kept) {
    (void)area;
    cv::Mat region = cv::Mat::zeros(binary.size(), CV_8U);
    region.setTo(255, labels == k);
    fill_holes(binary, region);
    cv::dilate(region, region, dilation_kernel(p));
    ClusterRegion r;
    r.width = image.width, r.height = image.height, r.otsu_threshold = threshold;
    region_geometry(region, p, r);
    if (r.found()) out.push_back(std::move(r));
  }
  return out;
}

const ParamTable<ClusterSegmentationParams>& cluster_segmentation_param_table() {
  using P = ClusterSegmentationParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .choice("component", &P::component,
                  {{"h_minus_i", P::Component::HueMinusIntensity}, {"cr", P::Component::Cr}},
                  "colour component thresholded by Otsu: H - I for summer black, Cr for red grapes (seed 001 Sect. "
                  "2.2.2.1)")
          .integer("dilate_px", "px", &P::dilate_px, 0, 10,
                   "radius of the square kernel of both dilations (seed 001 Sect. 2.2.2.1; size not stated)")
          .integer("min_region_px", "px", &P::min_region_px, 0, 1000000,
                   "regions smaller than this are removed as noise (seed 001 Sect. 2.2.2.1; size not stated)")
          .integer("min_cluster_px", "px", &P::min_cluster_px, 1, 1000000,
                   "a largest region smaller than this means no cluster in the image");
  return table;
}

}  // namespace grapebench
