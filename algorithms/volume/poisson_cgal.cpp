#include "algorithms/volume/poisson_cgal.h"

#include "algorithms/volume/grid_contour.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Poisson_reconstruction_function.h>
#include <CGAL/grid_simplify_point_set.h>
#include <CGAL/property_map.h>

#include <cmath>
#include <utility>

namespace grapebench {

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
  contour_grid(values, n, lo, step, out.vertices, out.triangles);
  return out;
}

}  // namespace grapebench
