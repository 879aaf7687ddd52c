// The only translation unit of algorithms/ that includes CGAL's alpha shapes.
#include "algorithms/volume/alpha_shape_volume.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Fixed_alpha_shape_3.h>
#include <CGAL/Fixed_alpha_shape_cell_base_3.h>
#include <CGAL/Fixed_alpha_shape_vertex_base_3.h>

#include <algorithm>
#include <map>

namespace grapebench {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Fixed_alpha_shape_vertex_base_3<K>;
using Cb = CGAL::Fixed_alpha_shape_cell_base_3<K>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using Delaunay = CGAL::Delaunay_triangulation_3<K, Tds>;
using AlphaShape = CGAL::Fixed_alpha_shape_3<Delaunay>;

Vec3 vec(const K::Point_3& p) { return {p.x(), p.y(), p.z()}; }
bool lex_less(const Vec3& a, const Vec3& b) { return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3); }
}  // namespace

VolumeEstimate alpha_shape_volume(const PointCloud& cloud, const AlphaShapeParams& params) {
  require_solid(cloud, "alpha_shape_volume");
  if (!(params.alpha >= 1e-4 && params.alpha <= 10)) {
    throw InputError("alpha_shape_volume: alpha " + std::to_string(params.alpha) + " m is outside [0.0001, 10]");
  }
  std::vector<K::Point_3> pts;
  pts.reserve(static_cast<std::size_t>(cloud.rows()));
  for (Eigen::Index i = 0; i < cloud.rows(); ++i) pts.emplace_back(cloud(i, 0), cloud(i, 1), cloud(i, 2));
  AlphaShape as(pts.begin(), pts.end(), params.alpha * params.alpha);

  std::vector<AlphaShape::Cell_handle> cells;
  as.get_alpha_shape_cells(std::back_inserter(cells), AlphaShape::INTERIOR);
  // Each tetrahedron from its vertices in lexicographic order, then a sorted sum:
  // the result does not depend on CGAL's internal cell order.
  std::vector<double> volumes;
  volumes.reserve(cells.size());
  for (const auto& c : cells) {
    std::array<Vec3, 4> v;
    for (int k = 0; k < 4; ++k) v[k] = vec(c->vertex(k)->point());
    std::sort(v.begin(), v.end(), lex_less);
    volumes.push_back(std::abs((v[1] - v[0]).dot((v[2] - v[0]).cross(v[3] - v[0]))) / 6.0);
  }
  std::sort(volumes.begin(), volumes.end());
  VolumeEstimate out;
  for (double x : volumes) out.volume += x;

  // Boundary: regular facets, oriented away from their interior cell.
  std::vector<AlphaShape::Facet> facets;
  as.get_alpha_shape_facets(std::back_inserter(facets), AlphaShape::REGULAR);
  std::map<std::array<double, 3>, int> index;
  auto vertex = [&](const Vec3& p) {
    const std::array<double, 3> key{p.x(), p.y(), p.z()};
    const auto it = index.find(key);
    if (it != index.end()) return it->second;
    out.mesh_vertices.push_back(p);
    return index[key] = static_cast<int>(out.mesh_vertices.size()) - 1;
  };
  std::map<std::pair<int, int>, int> edge_use;  // for the watertightness check
  for (auto f : facets) {
    if (as.classify(f.first) != AlphaShape::INTERIOR) f = as.mirror_facet(f);
    const auto c = f.first;
    const int i = f.second;
    std::array<Vec3, 3> t;
    for (int k = 0, j = 0; k < 4; ++k) {
      if (k != i) t[j++] = vec(c->vertex(k)->point());
    }
    const Vec3 inside = vec(c->vertex(i)->point());
    if ((t[1] - t[0]).cross(t[2] - t[0]).dot(inside - t[0]) > 0) std::swap(t[1], t[2]);
    std::array<int, 3> tri{vertex(t[0]), vertex(t[1]), vertex(t[2])};
    for (int k = 0; k < 3; ++k) ++edge_use[std::minmax(tri[k], tri[(k + 1) % 3])];
    out.mesh_triangles.push_back(tri);
  }
  out.watertight = !out.mesh_triangles.empty() &&
                   std::all_of(edge_use.begin(), edge_use.end(), [](const auto& e) { return e.second % 2 == 0; });
  out.points_used = pts.size();
  out.notes = std::to_string(cells.size()) + " interior tetrahedra, " + std::to_string(facets.size()) +
              " boundary facets, alpha radius " + std::to_string(params.alpha) + " m";
  return out;
}

const ParamTable<AlphaShapeParams>& alpha_shape_param_table() {
  static const ParamTable<AlphaShapeParams> table = ParamTable<AlphaShapeParams>().real(
      "alpha", "m", &AlphaShapeParams::alpha, 1e-4, 10, "alpha as a ball radius (seed 000: 0.25, read as dm)");
  return table;
}

}  // namespace grapebench
