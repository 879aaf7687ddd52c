#include "algorithms/stereo/berry_circles.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace grapebench {

RadiusWindow berry_radius_window(const BerryCircleParams& p, double depth, double fx) {
  if (p.radius_model == BerryCircleParams::RadiusModel::Pinhole) {
    return {fx * p.berry_radius_min / depth, fx * p.berry_radius_max / depth};
  }
  // Eq. 6 with r_t and z in mm. The text swaps the names r_min and r_max.
  const double k = 3185.0 * std::pow(depth * 1e3, -1.16);
  return {k * p.berry_radius_min * 1e3, k * p.berry_radius_max * 1e3};
}

std::optional<Circle> fit_circle(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  if (n < 3) return std::nullopt;
  // Kasa: minimise sum (x^2 + y^2 + D x + E y + F)^2, centred for conditioning.
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) mx += x[i], my += y[i];
  mx /= double(n), my /= double(n);
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const double u = x[i] - mx, v = y[i] - my;
    const Eigen::Vector3d row(u, v, 1);
    A += row * row.transpose();
    b -= row * (u * u + v * v);
  }
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(A);
  if (lu.rank() < 3) return std::nullopt;
  const Eigen::Vector3d s = lu.solve(b);
  const double cx = -0.5 * s(0), cy = -0.5 * s(1), r2 = cx * cx + cy * cy - s(2);
  if (!(r2 > 0) || !std::isfinite(r2)) return std::nullopt;
  return Circle{cx + mx, cy + my, std::sqrt(r2)};
}

BerryCircles detect_berries(const RgbImage& image, const ClusterRegion& region, double depth, double fx,
                            const BerryCircleParams& p) {
  BerryCircles out;
  out.window = berry_radius_window(p, depth, fx);
  if (!region.found()) return out;
  const RadiusWindow& w = out.window;
  // The cluster's bounding rectangle, widened by the largest radius (circles may reach out).
  const int pad = static_cast<int>(std::ceil(w.r_max));
  const int x0 = std::max(0, region.x0 - pad), y0 = std::max(0, region.y0 - pad);
  const int x1 = std::min(image.width - 1, region.x1 + pad), y1 = std::min(image.height - 1, region.y1 + pad);
  const cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.data.data()));
  cv::Mat grey, smooth, edges;
  cv::cvtColor(rgb(cv::Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1)), grey, cv::COLOR_RGB2GRAY);
  cv::GaussianBlur(grey, smooth, cv::Size(0, 0), p.blur_sigma);
  std::vector<cv::Vec4f> found;  // x, y, r, votes
  const int r_lo = std::max(1, static_cast<int>(std::floor(w.r_min))), r_hi = static_cast<int>(std::ceil(w.r_max));
  cv::HoughCircles(smooth, found, cv::HOUGH_GRADIENT, 1, std::max(1.0, 2 * w.r_min), p.canny_high, p.accumulator_votes,
                   r_lo, r_hi);
  out.candidates = static_cast<int>(found.size());
  // The refit's edge points: HoughCircles' own Canny (param1, param1 / 2).
  cv::Canny(smooth, edges, 0.5 * p.canny_high, p.canny_high);
  std::vector<cv::Point> edge_pts;
  cv::findNonZero(edges, edge_pts);
  // The points come row by row (sorted by y). A circle's band is looked for only in the
  // rows and columns it spans (a margin of 1 px beyond), in the same order: the same
  // points as testing all of them, which on textured images (17,000 edge points and 26
  // circles a pair) took a fifth of the berry stage.
  const auto row_begin = [&](int y) {
    return std::partition_point(edge_pts.begin(), edge_pts.end(), [y](const cv::Point& e) { return e.y < y; });
  };

  std::vector<Detection> kept;
  std::vector<double> ex, ey;
  for (const cv::Vec4f& f : found) {
    Circle c{f[0], f[1], f[2]};
    ex.clear(), ey.clear();
    const double reach = c.r + p.refit_band + 1;
    const auto end = row_begin(static_cast<int>(std::ceil(c.y + reach)) + 1);
    for (auto e = row_begin(static_cast<int>(std::floor(c.y - reach))); e != end; ++e) {
      if (std::abs(e->x - c.x) > reach) continue;
      if (std::abs(std::hypot(e->x - c.x, e->y - c.y) - c.r) <= p.refit_band) ex.push_back(e->x), ey.push_back(e->y);
    }
    if (static_cast<int>(ex.size()) >= p.min_refit_points) {
      if (auto fit = fit_circle(ex, ey); fit && std::hypot(fit->x - c.x, fit->y - c.y) < c.r) {
        c = *fit;
        ++out.refitted;
      }
    }
    c.x += x0, c.y += y0;
    // Eq. 7, rules 2 and 3: the centre on S_GC, r_min < r < r_max.
    const int u = static_cast<int>(std::lround(c.x)), v = static_cast<int>(std::lround(c.y));
    if (u < 0 || v < 0 || u >= image.width || v >= image.height) continue;
    if (!region.mask[static_cast<std::size_t>(v) * image.width + u]) continue;
    if (!(c.r > w.r_min && c.r < w.r_max)) continue;
    kept.push_back({c, f[3]});
  }
  // Eq. 7, rule 1: centres at least 2 r_min apart; the circle with fewer votes goes.
  std::stable_sort(kept.begin(), kept.end(), [](const Detection& a, const Detection& b) { return a.score > b.score; });
  for (const Detection& d : kept) {
    const bool clash = std::any_of(out.berries.begin(), out.berries.end(), [&](const Detection& o) {
      return std::hypot(o.circle.x - d.circle.x, o.circle.y - d.circle.y) < 2 * w.r_min;
    });
    if (!clash) out.berries.push_back(d);
  }
  return out;
}

const ParamTable<BerryCircleParams>& berry_circle_param_table() {
  using P = BerryCircleParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("berry_radius_min", "m", &P::berry_radius_min, 0.001, 0.05,
                "r_t of the smallest berry, for r_min (seed 001 Sect. 2.2.2.4: 8 mm)")
          .real("berry_radius_max", "m", &P::berry_radius_max, 0.001, 0.05,
                "r_t of the largest berry, for r_max (seed 001 Sect. 2.2.2.4: 20 mm)")
          .choice("radius_model", &P::radius_model,
                  {{"eq6", P::RadiusModel::Eq6}, {"pinhole", P::RadiusModel::Pinhole}},
                  "pixel radius at depth z: the paper's fit r = 3185 r_t z^-1.16 (seed 001 Eq. 6) or f r_t / z")
          .real("accumulator_votes", "votes", &P::accumulator_votes, 1, 1000,
                "gradient Hough accumulator threshold (seed 001 Sect. 2.2.2.4: 13)")
          .real("canny_high", "grey", &P::canny_high, 1, 1000, "Canny high threshold of the circle edges (not stated)")
          .real("blur_sigma", "px", &P::blur_sigma, 0.1, 10, "Gaussian smoothing before the edges (not stated)")
          .real("refit_band", "px", &P::refit_band, 0.5, 20, "edge points this close to a circle refit it")
          .integer("min_refit_points", "count", &P::min_refit_points, 3, 10000,
                   "fewer edge points keep the Hough circle as it is")
          .validate([](const P& p, const ConfigNode& n) {
            if (p.berry_radius_min >= p.berry_radius_max) n.fail("berry_radius_min", "must be below berry_radius_max");
          });
  return table;
}

}  // namespace grapebench
