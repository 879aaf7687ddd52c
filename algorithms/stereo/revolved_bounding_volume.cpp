#include "algorithms/stereo/revolved_bounding_volume.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_2.h>

#include <algorithm>
#include <cmath>

namespace grapebench {

RevolvedBoundingVolume revolved_bounding_volume(const Vec3& origin, const std::vector<Vec3>& points) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<K::Point_2> section{{0, 0}};
  RevolvedBoundingVolume out;
  double l_max = 0;
  for (const Vec3& p : points) {
    const Vec3 d = p - origin;
    const double l = std::hypot(d.x(), d.z());  // Eq. 9
    l_max = std::max(l_max, l);
    section.emplace_back(l, d.y());
    section.emplace_back(0, d.y());
  }
  std::vector<K::Point_2> hull;
  CGAL::convex_hull_2(section.begin(), section.end(), std::back_inserter(hull));
  double moment6 = 0, y_lo = 0, y_hi = 0;  // 6 A x_c (shoelace); Pappus needs no A alone
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const K::Point_2& a = hull[i];
    const K::Point_2& b = hull[(i + 1) % hull.size()];
    const double cross = a.x() * b.y() - b.x() * a.y();
    moment6 += (a.x() + b.x()) * cross;
    y_lo = std::min(y_lo, a.y());
    y_hi = std::max(y_hi, a.y());
    out.section.emplace_back(a.x(), a.y());
  }
  // Pappus: V = 2 pi A x_c = 2 pi (moment6 / 6); sign-free (orientation).
  out.volume = std::abs(2 * M_PI * moment6 / 6.0);
  out.height = y_hi - y_lo;
  out.max_diameter = 2 * l_max;
  return out;
}

}  // namespace grapebench
