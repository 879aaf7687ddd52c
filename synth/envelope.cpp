// The only translation unit of synth/ that includes CGAL (compile time).
#include "synth/config.h"
#include "synth/ground_truth.h"
#include "synth/stem_geometry.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace grapebench {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;

Vec3 to_vec(const Kernel::Point_3& p) { return {p.x(), p.y(), p.z()}; }

// Akl-Toussaint: a point strictly inside the hull of some of the points is no hull
// vertex. Dropping those first spares CGAL's quickhull most of its point-against-plane
// tests (90 % of its time on a 50k-point bunch); the hull, and so its exact volume,
// stays the same. The inner polytope is the hull of the points extreme in 128
// directions among a sample of the cloud (any points of it will do) and along the
// axes. Points are binned on a coarse grid: a cell inside every plane drops all its
// points at once, and the points of the others are tested only against the planes
// that cut their cell. Inside means by a margin of 1e-9 of the cloud's size, far above
// the rounding of the planes.
std::vector<Kernel::Point_3> hull_candidates(const std::vector<Vec3>& points) {
  const std::size_t n = points.size();
  const auto point = [&](std::size_t i) { return Kernel::Point_3(points[i].x(), points[i].y(), points[i].z()); };
  std::vector<Kernel::Point_3> all;
  if (n < 1000) {
    for (std::size_t i = 0; i < n; ++i) all.push_back(point(i));
    return all;
  }
  Vec3 lo = points[0], hi = points[0];
  std::array<std::size_t, 6> axis_extreme{};
  for (std::size_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      if (points[i][a] < lo[a]) lo[a] = points[i][a], axis_extreme[static_cast<std::size_t>(2 * a)] = i;
      if (points[i][a] > hi[a]) hi[a] = points[i][a], axis_extreme[static_cast<std::size_t>(2 * a + 1)] = i;
    }
  }
  constexpr int kDirections = 128;  // a spherical Fibonacci lattice
  std::vector<std::size_t> corner_index(axis_extreme.begin(), axis_extreme.end());
  const std::size_t stride = std::max<std::size_t>(1, n / 4096);
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int k = 0; k < kDirections; ++k) {
    const double z = 1 - (2.0 * k + 1) / kDirections, r = std::sqrt(1 - z * z);
    const Vec3 d(r * std::cos(golden * k), r * std::sin(golden * k), z);
    std::size_t best = 0;
    double reach = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; i += stride) {
      const double t = d.dot(points[i]);
      if (t > reach) reach = t, best = i;
    }
    corner_index.push_back(best);
  }
  std::sort(corner_index.begin(), corner_index.end());
  corner_index.erase(std::unique(corner_index.begin(), corner_index.end()), corner_index.end());
  std::vector<Kernel::Point_3> corners;
  for (auto i : corner_index) corners.push_back(point(i));
  Mesh inner;
  CGAL::convex_hull_3(corners.begin(), corners.end(), inner);
  std::vector<Eigen::Vector4d> planes;  // outward unit normal, offset
  for (auto f : inner.faces()) {
    std::array<Vec3, 3> v;
    std::size_t k = 0;
    for (auto h : CGAL::halfedges_around_face(inner.halfedge(f), inner)) v[k++] = to_vec(inner.point(inner.target(h)));
    const Vec3 nrm = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
    if (!nrm.allFinite()) {  // a sliver facet: no filter
      planes.clear();
      break;
    }
    planes.emplace_back(nrm.x(), nrm.y(), nrm.z(), std::max({nrm.dot(v[0]), nrm.dot(v[1]), nrm.dot(v[2])}));
  }
  if (inner.number_of_faces() < 4 || planes.empty()) {
    for (std::size_t i = 0; i < n; ++i) all.push_back(point(i));
    return all;
  }
  const double margin = 1e-9 * (hi - lo).norm();
  // The grid: about 16 points per cell.
  const int g = std::clamp(static_cast<int>(std::cbrt(static_cast<double>(n) / 16)), 1, 64);
  const Vec3 size = ((hi - lo) / g).cwiseMax(Vec3::Constant(1e-300));
  const auto cell_of = [&](const Vec3& q) {
    int c[3];
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>((q[a] - lo[a]) / size[a]), 0, g - 1);
    return static_cast<std::size_t>(c[0] + g * (c[1] + g * c[2]));
  };
  // Per cell, the planes its box reaches past (-1: not yet known).
  std::vector<int> first_plane(static_cast<std::size_t>(g) * g * g + 1, -1), plane_count(first_plane.size(), 0);
  std::vector<int> cut;  // plane indices, cell by cell
  std::vector<char> keep(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t c = cell_of(points[i]);
    if (first_plane[c] < 0) {
      const int cx = static_cast<int>(c % static_cast<std::size_t>(g)), cy = static_cast<int>(c / static_cast<std::size_t>(g) % static_cast<std::size_t>(g)),
                cz = static_cast<int>(c / static_cast<std::size_t>(g * g));
      // Cells at the grid's top edge also hold the points on it: half a cell more.
      const Vec3 centre = lo + size.cwiseProduct(Vec3(cx + 0.5, cy + 0.5, cz + 0.5));
      const Vec3 half = 0.5 * size + 0.5 * size.cwiseProduct(Vec3(cx == g - 1, cy == g - 1, cz == g - 1));
      first_plane[c] = static_cast<int>(cut.size());
      for (std::size_t k = 0; k < planes.size(); ++k) {
        const Vec3 nrm = planes[k].head<3>();
        if (nrm.dot(centre) + nrm.cwiseAbs().dot(half) + margin >= planes[k][3] - margin) cut.push_back(static_cast<int>(k));
      }
      plane_count[c] = static_cast<int>(cut.size()) - first_plane[c];
    }
    for (int k = first_plane[c]; k < first_plane[c] + plane_count[c]; ++k) {
      const Eigen::Vector4d& pl = planes[static_cast<std::size_t>(cut[static_cast<std::size_t>(k)])];
      if (pl.head<3>().dot(points[i]) > pl[3] - margin) {
        keep[i] = 1;
        break;
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (keep[i]) all.push_back(point(i));
  return all;
}

Mesh hull_of(const std::vector<Vec3>& points) {
  if (points.size() < 4) throw InputError("convex hull needs at least 4 points");
  for (const auto& x : points)
    if (!x.allFinite()) throw InputError("convex hull input has a non-finite point");
  const std::vector<Kernel::Point_3> p = hull_candidates(points);
  Mesh m;
  CGAL::convex_hull_3(p.begin(), p.end(), m);
  if (m.number_of_faces() < 4) throw InputError("convex hull input points are coplanar");
  return m;
}

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
