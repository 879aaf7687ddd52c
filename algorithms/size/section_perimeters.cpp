#include "algorithms/size/section_perimeters.h"

#include "algorithms/size/hobby_spline.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_2.h>

#include <cmath>
#include <map>

namespace grapebench {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

// Counter-clockwise outline of slice points.
std::vector<Vec2> outline_of(const std::vector<Vec2>& pts, const SectionPerimeterParams& p, const Vec2& centre) {
  std::vector<Vec2> out;
  if (p.outline == SectionPerimeterParams::Outline::ConvexHull) {
    std::vector<K::Point_2> in, hull;
    in.reserve(pts.size());
    for (const auto& q : pts) in.emplace_back(q.x(), q.y());
    CGAL::convex_hull_2(in.begin(), in.end(), std::back_inserter(hull));
    for (const auto& h : hull) out.emplace_back(h.x(), h.y());
    return out;
  }
  // angular: the farthest point from the centre in each sector, in angle order.
  std::map<int, std::pair<double, Vec2>> best;
  for (const auto& q : pts) {
    const Vec2 d = q - centre;
    const double r = d.norm();
    if (!(r > 0)) continue;
    const double a = std::atan2(d.y(), d.x()) + M_PI;  // [0, 2 pi]
    const int bin = std::min(p.angular_bins - 1, static_cast<int>(a / (2 * M_PI) * p.angular_bins));
    auto it = best.find(bin);
    if (it == best.end() || r > it->second.first) best[bin] = {r, q};
  }
  for (const auto& [bin, v] : best) out.push_back(v.second);
  return out;
}

}  // namespace

SectionPerimeters section_perimeters(const PointCloud& cloud, const SectionPerimeterParams& p) {
  if (!(p.half_width >= 1e-4 && p.half_width <= 0.05)) throw InputError("section_perimeters: half_width must lie in [1e-4, 0.05] m");
  if (p.angular_bins < 8 || p.angular_bins > 3600) throw InputError("section_perimeters: angular_bins must lie in [8, 3600]");
  SectionPerimeters s;
  s.box = pca_box(cloud);
  const Vec3 mid = 0.5 * (s.box.minimum + s.box.maximum);  // box centre, PCA frame (seed 002 Eq. 8)
  static const char* names[3] = {"height", "length", "width"};
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    std::vector<Vec2> slice;
    for (Eigen::Index i = 0; i < cloud.rows(); ++i) {
      const Vec3 local = s.box.axes.transpose() * (cloud.row(i).transpose() - s.box.centre);
      if (std::abs(local(k) - mid(k)) <= p.half_width) slice.emplace_back(local(a), local(b));
    }
    s.slice_points[static_cast<std::size_t>(k)] = static_cast<int>(slice.size());
    std::vector<Vec2> knots = outline_of(slice, p, Vec2(mid(a), mid(b)));
    // Drop repeated knots (coincident points) so every chord has a length.
    std::vector<Vec2> clean;
    for (const auto& q : knots) {
      if (clean.empty() || (q - clean.back()).norm() > 1e-9) clean.push_back(q);
    }
    while (clean.size() > 1 && (clean.front() - clean.back()).norm() <= 1e-9) clean.pop_back();
    if (clean.size() < 3) {
      throw InputError(std::string("section_perimeters: the section normal to the ") + names[k] + " axis has " +
                       std::to_string(clean.size()) + " outline points (" + std::to_string(slice.size()) +
                       " in the slice); needs 3. Widen half_width?");
    }
    s.knots[static_cast<std::size_t>(k)] = static_cast<int>(clean.size());
    s.perimeter(k) = spline_length(closed_hobby_spline(clean, p.tension));
  }
  return s;
}

const ParamTable<SectionPerimeterParams>& section_perimeter_param_table() {
  using P = SectionPerimeterParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("half_width", "m", &P::half_width, 1e-4, 0.05,
                "half thickness of each slice (seed 002 Sect. 3.2: truth within 3 mm of the centroid)")
          .choice("outline", &P::outline, {{"convex_hull", P::Outline::ConvexHull}, {"angular", P::Outline::Angular}},
                  "slice outline: convex hull (a tape) or farthest point per sector (seed 002's quadrants)")
          .integer("angular_bins", "count", &P::angular_bins, 8, 3600, "sectors of the angular outline")
          .when("outline: angular", [](const P& p) { return p.outline == P::Outline::Angular; })
          .real("tension", "-", &P::tension, 0.75, 4, "Hobby spline tension (seed 002 Eqs. 10-11)");
  return table;
}

}  // namespace grapebench
