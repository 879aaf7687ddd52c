#include "algorithms/poisson_cgal.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Poisson_reconstruction_function.h>
#include <CGAL/grid_simplify_point_set.h>
#include <CGAL/property_map.h>

#include <cmath>
#include <unordered_map>
#include <utility>

namespace grapebench {

namespace {

// Marching tetrahedra over the grid values (negative inside), each cube split into
// the six tetrahedra of Kuhn's decomposition, which neighbouring cubes share faces
// with, so the surface closes. Surface vertices sit on grid edges and are shared
// through the edge's node pair, so the mesh is indexed and closed.
class Contour {
 public:
  Contour(const std::vector<double>& f, const std::array<int, 3>& n, const Vec3& origin, double step, CgalPoissonMesh& out)
      : f_(f), n_(n), origin_(origin), step_(step), out_(out) {}

  void run() {
    // Kuhn: the six monotone paths from corner (0,0,0) to (1,1,1).
    static constexpr int kAxisOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int z = 0; z + 1 < n_[2]; ++z) {
      for (int y = 0; y + 1 < n_[1]; ++y) {
        for (int x = 0; x + 1 < n_[0]; ++x) {
          if (uniform_cube({x, y, z})) continue;  // most of the grid: no surface
          for (const auto& order : kAxisOrders) {
            std::array<int, 3> c{x, y, z};
            std::array<std::int64_t, 4> tet{};
            tet[0] = node(c);
            for (int k = 0; k < 3; ++k) {
              ++c[static_cast<std::size_t>(order[k])];
              tet[static_cast<std::size_t>(k + 1)] = node(c);
            }
            tetrahedron(tet);
          }
        }
      }
    }
  }

 private:
  std::int64_t node(const std::array<int, 3>& c) const {
    return (static_cast<std::int64_t>(c[2]) * n_[1] + c[1]) * n_[0] + c[0];
  }
  Vec3 position(std::int64_t id) const {
    const std::int64_t x = id % n_[0], y = (id / n_[0]) % n_[1], z = id / (static_cast<std::int64_t>(n_[0]) * n_[1]);
    return origin_ + step_ * Vec3(static_cast<double>(x), static_cast<double>(y), static_cast<double>(z));
  }
  bool inside(std::int64_t id) const { return f_[static_cast<std::size_t>(id)] < 0; }
  // True when the cube's eight corners lie on the same side, so none of its
  // tetrahedra is cut.
  bool uniform_cube(const std::array<int, 3>& c) const {
    const bool first = inside(node(c));
    for (int corner = 1; corner < 8; ++corner) {
      const std::array<int, 3> q{c[0] + (corner & 1), c[1] + ((corner >> 1) & 1), c[2] + ((corner >> 2) & 1)};
      if (inside(node(q)) != first) return false;
    }
    return true;
  }

  // The surface vertex on the edge (a inside, b outside), linearly interpolated.
  int edge_vertex(std::int64_t a, std::int64_t b) {
    const std::int64_t lo = std::min(a, b), hi = std::max(a, b);
    const auto key = static_cast<std::uint64_t>(lo) * static_cast<std::uint64_t>(f_.size()) + static_cast<std::uint64_t>(hi);
    const auto [it, added] = edges_.try_emplace(key, static_cast<int>(out_.vertices.size()));
    if (added) {
      const double fa = f_[static_cast<std::size_t>(a)], fb = f_[static_cast<std::size_t>(b)];
      const double t = fa / (fa - fb);  // fa < 0 <= fb
      out_.vertices.push_back(position(a) + t * (position(b) - position(a)));
    }
    return it->second;
  }

  // A triangle facing from the inside nodes to the outside ones.
  void triangle(int i, int j, int k, const Vec3& towards_outside) {
    const Vec3& a = out_.vertices[static_cast<std::size_t>(i)];
    const Vec3 n = (out_.vertices[static_cast<std::size_t>(j)] - a).cross(out_.vertices[static_cast<std::size_t>(k)] - a);
    if (n.dot(towards_outside) >= 0) {
      out_.triangles.push_back({i, j, k});
    } else {
      out_.triangles.push_back({i, k, j});
    }
  }

  void tetrahedron(const std::array<std::int64_t, 4>& t) {
    std::array<std::int64_t, 4> in{}, outside{};
    int n_in = 0, n_out = 0;
    for (const auto v : t) (inside(v) ? in[static_cast<std::size_t>(n_in++)] : outside[static_cast<std::size_t>(n_out++)]) = v;
    if (n_in == 0 || n_out == 0) return;
    Vec3 ci = Vec3::Zero(), co = Vec3::Zero();
    for (int k = 0; k < n_in; ++k) ci += position(in[static_cast<std::size_t>(k)]) / n_in;
    for (int k = 0; k < n_out; ++k) co += position(outside[static_cast<std::size_t>(k)]) / n_out;
    const Vec3 dir = co - ci;
    if (n_in == 1 || n_out == 1) {
      // One node alone on its side: the triangle cuts its three edges.
      const bool lone_inside = n_in == 1;
      const std::int64_t lone = lone_inside ? in[0] : outside[0];
      std::array<int, 3> v{};
      for (int k = 0; k < 3; ++k) {
        const std::int64_t other = lone_inside ? outside[static_cast<std::size_t>(k)] : in[static_cast<std::size_t>(k)];
        v[static_cast<std::size_t>(k)] = lone_inside ? edge_vertex(lone, other) : edge_vertex(other, lone);
      }
      triangle(v[0], v[1], v[2], dir);
      return;
    }
    // Two and two: a quad through the four crossing edges, in cyclic order.
    const int a = edge_vertex(in[0], outside[0]), b = edge_vertex(in[0], outside[1]);
    const int c = edge_vertex(in[1], outside[1]), d = edge_vertex(in[1], outside[0]);
    triangle(a, b, c, dir);
    triangle(a, c, d, dir);
  }

  const std::vector<double>& f_;
  std::array<int, 3> n_;
  Vec3 origin_;
  double step_;
  CgalPoissonMesh& out_;
  std::unordered_map<std::uint64_t, int> edges_;
};

}  // namespace

CgalPoissonMesh cgal_poisson_mesh(const PointCloud& points, const PointCloud& normals, double cell, double step) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Pwn = std::pair<K::Point_3, K::Vector_3>;
  std::vector<Pwn> pwn;
  pwn.reserve(static_cast<std::size_t>(points.rows()));
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    pwn.emplace_back(K::Point_3(points(i, 0), points(i, 1), points(i, 2)),
                     K::Vector_3(normals(i, 0), normals(i, 1), normals(i, 2)));
  }
  const auto point_map = CGAL::First_of_pair_property_map<Pwn>();
  if (cell > 0) pwn.erase(CGAL::grid_simplify_point_set(pwn, cell, CGAL::parameters::point_map(point_map)), pwn.end());
  CgalPoissonMesh out;
  out.points_solved = pwn.size();
  CGAL::Poisson_reconstruction_function<K> f(pwn.begin(), pwn.end(), point_map, CGAL::Second_of_pair_property_map<Pwn>());
  // Also sets the contouring value (the median at the input points) to 0, negative inside.
  if (!f.compute_implicit_function()) return out;
  out.ok = true;

  Vec3 lo = points.colwise().minCoeff().transpose(), hi = points.colwise().maxCoeff().transpose();
  lo.array() -= 2 * step;
  hi.array() += 2 * step;
  std::array<int, 3> n{};
  for (int k = 0; k < 3; ++k) n[static_cast<std::size_t>(k)] = static_cast<int>(std::ceil((hi(k) - lo(k)) / step)) + 1;
  std::vector<double> values(static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(n[2]));
  // The function is evaluated here rather than by f(p): CGAL 5.5's operator()
  // dereferences its null cell hint on the first call (UBSan: reference binding to
  // null pointer). Same interpolation: linear in the located Delaunay cell; outside
  // the hull, the value of a finite vertex of the infinite cell. Raster order, each
  // location starting from the last one's cell.
  const auto& tr = f.tr();
  decltype(tr.infinite_cell()) hint;
  std::size_t i = 0;
  for (int z = 0; z < n[2]; ++z) {
    for (int y = 0; y < n[1]; ++y) {
      for (int x = 0; x < n[0]; ++x) {
        const K::Point_3 q(lo.x() + x * step, lo.y() + y * step, lo.z() + z * step);
        hint = tr.locate(q, hint);
        if (tr.is_infinite(hint)) {
          values[i++] = hint->vertex((hint->index(tr.infinite_vertex()) + 1) & 3)->f();
          continue;
        }
        const auto at = [&](int k) {
          const auto& v = hint->vertex(k)->point();
          return Vec3(v.x(), v.y(), v.z());
        };
        const Vec3 d = at(3);
        Eigen::Matrix3d m;
        m << at(0) - d, at(1) - d, at(2) - d;
        const Vec3 w = m.partialPivLu().solve(Vec3(q.x(), q.y(), q.z()) - d);
        values[i++] = w(0) * hint->vertex(0)->f() + w(1) * hint->vertex(1)->f() + w(2) * hint->vertex(2)->f() +
                      (1 - w.sum()) * hint->vertex(3)->f();
      }
    }
  }
  out.grid_nodes = values.size();
  Contour(values, n, lo, step, out).run();
  return out;
}

}  // namespace grapebench
