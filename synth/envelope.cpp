// The only translation unit of synth/ that includes CGAL (compile time).
#include "synth/config.h"
#include "synth/ground_truth.h"
#include "synth/stem_geometry.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>

#include <array>
#include <cmath>

namespace grapebench {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;

Mesh hull_of(const std::vector<Vec3>& points) {
  if (points.size() < 4) throw InputError("convex hull needs at least 4 points");
  std::vector<Kernel::Point_3> p;
  p.reserve(points.size());
  for (const auto& x : points) {
    if (!x.allFinite()) throw InputError("convex hull input has a non-finite point");
    p.emplace_back(x.x(), x.y(), x.z());
  }
  Mesh m;
  CGAL::convex_hull_3(p.begin(), p.end(), m);
  if (m.number_of_faces() < 4) throw InputError("convex hull input points are coplanar");
  return m;
}

Vec3 to_vec(const Kernel::Point_3& p) { return {p.x(), p.y(), p.z()}; }

// Exact rational sum of the facet tetrahedra: the exact volume does not depend on
// CGAL's facet order or on how coplanar points were triangulated, so its rounding
// is the same in every run and on every thread.
double exact_volume(const Mesh& m) {
  using Q = CGAL::Exact_rational;
  Q six_volume = 0;
  for (auto f : m.faces()) {
    std::array<std::array<Q, 3>, 3> v;
    int k = 0;
    for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
      const auto& p = m.point(m.target(h));
      v[k++] = {Q(p.x()), Q(p.y()), Q(p.z())};
    }
    six_volume += v[0][0] * (v[1][1] * v[2][2] - v[1][2] * v[2][1]) -
                  v[0][1] * (v[1][0] * v[2][2] - v[1][2] * v[2][0]) +
                  v[0][2] * (v[1][0] * v[2][1] - v[1][1] * v[2][0]);
  }
  return CGAL::to_double(six_volume / 6);
}


// Unit-sphere sample (spherical Fibonacci lattice) and the inradius of its hull:
// the hull contains the ball of that radius, so scaling the sample by its inverse
// gives a polytope containing the unit sphere.
struct SphereSample {
  std::vector<Vec3> points;
  double inradius = 1;
};
const SphereSample& sphere_sample() {
  static const SphereSample s = [] {
    SphereSample out;
    const int n = 1600;
    const double golden = M_PI * (3 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
      const double z = 1 - (2.0 * i + 1) / n, r = std::sqrt(1 - z * z);
      out.points.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
    }
    convex_hull_volume(out.points, &out.inradius);
    // Rounded down to 1e-12: still a lower bound, and free of last-bit noise.
    out.inradius = std::floor(out.inradius * 1e12 - 1) * 1e-12;
    return out;
  }();
  return s;
}
}  // namespace

double convex_hull_volume(const std::vector<Vec3>& points, double* min_facet_distance,
                          const Vec3& origin) {
  const Mesh m = hull_of(points);
  if (min_facet_distance) {
    double best = std::numeric_limits<double>::infinity();
    for (auto f : m.faces()) {
      std::vector<Vec3> v;
      for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) v.push_back(to_vec(m.point(m.target(h))));
      const Vec3 n = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
      best = std::min(best, n.dot(v[0] - origin));
    }
    *min_facet_distance = best;
  }
  return exact_volume(m);
}

HullMesh convex_hull(const std::vector<Vec3>& points) {
  const Mesh m = hull_of(points);
  HullMesh out;
  std::vector<int> index(m.number_of_vertices(), -1);
  for (auto v : m.vertices()) {
    index[v.idx()] = static_cast<int>(out.vertices.size());
    out.vertices.push_back(to_vec(m.point(v)));
  }
  for (auto f : m.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) t[k++] = index[m.target(h).idx()];
    out.triangles.push_back(t);
  }
  out.volume = exact_volume(m);
  return out;
}

double convex_perimeter_2d(const std::vector<Eigen::Vector2d>& points) {
  using K2 = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<K2::Point_2> in, hull;
  in.reserve(points.size());
  for (const auto& p : points) in.emplace_back(p.x(), p.y());
  CGAL::convex_hull_2(in.begin(), in.end(), std::back_inserter(hull));
  if (hull.size() < 2) return 0;
  double total = 0;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const auto& p = hull[i];
    const auto& q = hull[(i + 1) % hull.size()];
    total += std::hypot(q.x() - p.x(), q.y() - p.y());
  }
  return total;
}

std::vector<Eigen::Vector4d> convex_hull_planes(const std::vector<Vec3>& points) {
  const Mesh m = hull_of(points);
  std::vector<Eigen::Vector4d> planes;
  for (auto f : m.faces()) {
    std::vector<Vec3> v;
    for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) v.push_back(to_vec(m.point(m.target(h))));
    const Vec3 n = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
    planes.emplace_back(n.x(), n.y(), n.z(), n.dot(v[0]));
  }
  return planes;
}

void envelope_bounds(const Bunch& bunch, double& lower, double& upper) {
  const SphereSample& unit = sphere_sample();
  // Balls deep inside the hull of the berry centres cannot touch the envelope.
  std::vector<Vec3> centres;
  for (const auto& b : bunch.berries) centres.push_back(b.centre);
  std::vector<Eigen::Vector4d> planes;
  if (centres.size() >= 4) {
    try {
      planes = convex_hull_planes(centres);
    } catch (const InputError&) {
      planes.clear();  // flat set of centres: keep every ball
    }
  }
  std::vector<Vec3> inner, outer;
  for (const auto& b : bunch.berries) {
    double depth = planes.empty() ? -1 : std::numeric_limits<double>::infinity();
    for (const auto& pl : planes) depth = std::min(depth, pl[3] - pl.head<3>().dot(b.centre));
    if (depth >= b.radius * (1 + 1e-9)) continue;
    for (const auto& u : unit.points) {
      inner.push_back(b.centre + b.radius * u);
      outer.push_back(b.centre + (b.radius / unit.inradius) * u);
    }
  }
  // A cylinder's hull is the hull of its two rims; a regular m-gon inscribed in a rim,
  // and the same scaled by 1/cos(pi/m) circumscribed.
  const int m = 48;
  const double grow = 1.0 / std::cos(M_PI / m);
  for (const auto& s : bunch.stems) {
    const Vec3 d = (s.end - s.start).normalized();
    Vec3 e1, e2;
    perpendicular_basis(d, e1, e2);
    for (int k = 0; k < m; ++k) {
      const double phi = 2 * M_PI * k / m;
      const Vec3 off = s.radius * (std::cos(phi) * e1 + std::sin(phi) * e2);
      for (const Vec3& c : {s.start, s.end}) {
        inner.push_back(c + off);
        outer.push_back(c + grow * off);
      }
    }
  }
  lower = convex_hull_volume(inner);
  upper = convex_hull_volume(outer);
}

}  // namespace grapebench
