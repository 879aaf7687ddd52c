#include "synth/union_mesh.h"

#include "synth/config.h"
#include "synth/stem_geometry.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace grapebench {

namespace {

using ExactKernel = CGAL::Exact_predicates_exact_constructions_kernel;
using ExactMesh = CGAL::Surface_mesh<ExactKernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

ExactMesh::Vertex_index add(ExactMesh& m, const Vec3& p) { return m.add_vertex(ExactKernel::Point_3(p.x(), p.y(), p.z())); }

// Icosphere about `centre` whose enclosed volume is the ball's.
ExactMesh ball_piece(const Vec3& centre, double radius, const std::vector<Vec3>& unit,
                const std::vector<std::array<int, 3>>& faces, double volume_scale) {
  ExactMesh m;
  std::vector<ExactMesh::Vertex_index> v;
  for (const Vec3& u : unit) v.push_back(add(m, centre + radius * volume_scale * u));
  for (const auto& f : faces) m.add_face(v[static_cast<std::size_t>(f[0])], v[static_cast<std::size_t>(f[1])], v[static_cast<std::size_t>(f[2])]);
  return m;
}

// Coaxial segments start[k] -> end[k] with radii[k] as one stepped tube: a ring per
// segment end, a flat annulus where the radius changes, fan caps at both ends.
ExactMesh tube_piece(const std::vector<const Stem*>& chain, int sides) {
  const Vec3 a = chain.front()->start, b = chain.back()->end;
  const Vec3 d = (b - a).normalized();
  Vec3 e1, e2;
  perpendicular_basis(d, e1, e2);
  // Consecutive rings are turned half a side against each other (an antiprism), so no
  // two wall triangles are coplanar: Open3D's self-intersection test takes coplanar
  // pieces of one wall quad, split where another piece crosses, for a crossing. The
  // cross-section of an antiprism is quadratic along it (Simpson): per unit length
  // (A_end + 4 A_mid + A_end) / 6, A_end = (n/2) R^2 sin(2 pi/n), A_mid = n R^2
  // cos^2(pi/2n) sin(pi/n); R is set so that equals the disc's pi r^2.
  const double n = sides;
  const double area_per_r2 = (n * std::sin(2 * M_PI / n) + 4 * n * std::pow(std::cos(M_PI / (2 * n)), 2) * std::sin(M_PI / n)) / 6;
  const double scale = std::sqrt(M_PI / area_per_r2);
  double phase = 0;
  ExactMesh m;
  const auto ring = [&](const Vec3& c, double r) {
    std::vector<ExactMesh::Vertex_index> out;
    for (int k = 0; k < sides; ++k) {
      const double phi = 2 * M_PI * (k + phase) / sides;
      out.push_back(add(m, c + r * scale * (std::cos(phi) * e1 + std::sin(phi) * e2)));
    }
    return out;
  };
  // `q_ahead`: q is turned half a side forward of p (q[k] between p[k] and p[k+1]).
  const auto strip = [&](const std::vector<ExactMesh::Vertex_index>& p, const std::vector<ExactMesh::Vertex_index>& q,
                         bool q_ahead) {
    for (int k = 0; k < sides; ++k) {
      const auto k0 = static_cast<std::size_t>(k), k1 = static_cast<std::size_t>((k + 1) % sides);
      if (q_ahead) {
        m.add_face(p[k0], p[k1], q[k0]);
        m.add_face(p[k1], q[k1], q[k0]);
      } else {
        m.add_face(p[k0], p[k1], q[k1]);
        m.add_face(p[k0], q[k1], q[k0]);
      }
    }
  };
  const ExactMesh::Vertex_index start_centre = add(m, a);
  std::vector<ExactMesh::Vertex_index> previous = ring(a, chain.front()->radius);
  for (int k = 0; k < sides; ++k) {
    m.add_face(start_centre, previous[static_cast<std::size_t>((k + 1) % sides)], previous[static_cast<std::size_t>(k)]);
  }
  for (std::size_t j = 0; j < chain.size(); ++j) {
    // Rings at most eight side lengths apart: without them a pedicel's wall is two
    // triangles centimetres long, and their crossings with berries leave needles
    // that Open3D counts as self-intersections (measured: none watertight; with
    // rings every 4 or 8 sides, all).
    const double length = (chain[j]->end - chain[j]->start).norm();
    const double side = 2 * M_PI * chain[j]->radius * scale / sides;
    const int steps = std::max(1, static_cast<int>(std::ceil(length / (8 * side))));
    for (int k = 1; k <= steps; ++k) {
      const Vec3 c = chain[j]->start + (chain[j]->end - chain[j]->start) * (static_cast<double>(k) / steps);
      phase = 0.5 - phase;
      std::vector<ExactMesh::Vertex_index> next = ring(k == steps ? chain[j]->end : c, chain[j]->radius);
      strip(previous, next, phase > 0);
      previous = next;
    }
    if (j + 1 < chain.size() && chain[j + 1]->radius != chain[j]->radius) {
      std::vector<ExactMesh::Vertex_index> next = ring(chain[j]->end, chain[j + 1]->radius);
      strip(previous, next, false);  // the flat annulus: same phase
      previous = next;
    }
  }
  const ExactMesh::Vertex_index end_centre = add(m, b);
  for (int k = 0; k < sides; ++k) {
    m.add_face(end_centre, previous[static_cast<std::size_t>(k)], previous[static_cast<std::size_t>((k + 1) % sides)]);
  }
  return m;
}

// Distance from x to the surface of a finite cylinder (lateral wall or flat caps).
double stem_surface_distance(const Stem& s, const Vec3& x) {
  const Vec3 axis = s.end - s.start;
  const double len = axis.norm();
  const Vec3 d = axis / len;
  const double t = (x - s.start).dot(d);
  const double radial = (x - s.start - t * d).norm();
  const bool within_length = t >= 0 && t <= len;
  if (within_length && radial <= s.radius) return std::min({s.radius - radial, t, len - t});  // inside
  if (within_length) return radial - s.radius;
  const double along = t < 0 ? -t : t - len;
  const double out = std::max(0.0, radial - s.radius);
  return std::sqrt(along * along + out * out);
}

}  // namespace

TriMesh bunch_surface(const Bunch& bunch, const MeshOptions& o) {
  if (o.sphere_subdivisions < 0 || o.sphere_subdivisions > 6) throw InputError("mesh: sphere_subdivisions must be in [0, 6]");
  if (o.tube_sides < 3 || o.tube_sides > 256) throw InputError("mesh: tube_sides must be in [3, 256]");
  std::vector<Vec3> unit;
  std::vector<std::array<int, 3>> faces;
  unit_icosphere(o.sphere_subdivisions, unit, faces);
  double unit_volume = 0;
  for (const auto& f : faces) {
    unit_volume += unit[static_cast<std::size_t>(f[0])].dot(unit[static_cast<std::size_t>(f[1])].cross(unit[static_cast<std::size_t>(f[2])])) / 6;
  }
  const double ball_scale = std::cbrt(4.0 / 3.0 * M_PI / unit_volume);
  std::vector<ExactMesh> pieces;
  for (const Berry& b : bunch.berries) pieces.push_back(ball_piece(b.centre, b.radius, unit, faces, ball_scale));
  std::vector<int> stacked_child(bunch.stems.size(), -1);
  for (std::size_t i = 0; i < bunch.stems.size(); ++i) {
    if (bunch.stems[i].stacked_on >= 0) stacked_child[static_cast<std::size_t>(bunch.stems[i].stacked_on)] = static_cast<int>(i);
  }
  for (std::size_t i = 0; i < bunch.stems.size(); ++i) {
    if (bunch.stems[i].stacked_on >= 0) continue;  // part of its chain's tube
    std::vector<const Stem*> chain;
    for (int j = static_cast<int>(i); j >= 0; j = stacked_child[static_cast<std::size_t>(j)]) {
      chain.push_back(&bunch.stems[static_cast<std::size_t>(j)]);
    }
    pieces.push_back(tube_piece(chain, o.tube_sides));
  }
  if (pieces.empty()) return {};
  // Pairwise, level by level: each union stays small, and the order is fixed.
  while (pieces.size() > 1) {
    std::vector<ExactMesh> next;
    for (std::size_t i = 0; i + 1 < pieces.size(); i += 2) {
      ExactMesh out;
      if (!PMP::corefine_and_compute_union(pieces[i], pieces[i + 1], out)) {
        throw std::runtime_error("mesh: CGAL could not form the union of the bunch's pieces");
      }
      next.push_back(std::move(out));
    }
    if (pieces.size() % 2 == 1) next.push_back(std::move(pieces.back()));
    pieces = std::move(next);
  }
  // In doubles, then without needles: corefinement leaves slivers a few nanometres
  // wide where pieces cross, and tools that test self-intersection with a tolerance
  // (Open3D) count those as crossings. Needles (longest / shortest edge > 100) with an
  // edge under 10 um are collapsed and caps (an angle above 175 deg) flipped. Measured
  // on 7 bunches of two presets: Open3D finds no crossing and calls each watertight.
  using Double = CGAL::Surface_mesh<CGAL::Exact_predicates_inexact_constructions_kernel::Point_3>;
  // In a canonical order (vertices sorted by position, faces by their vertices): the
  // corefinement's output order follows memory addresses, which differ with the
  // thread a bunch runs on, and the clean-up below depends on the order.
  Double m;
  {
    const ExactMesh& exact = pieces.front();
    std::vector<std::pair<std::array<double, 3>, ExactMesh::Vertex_index>> points;
    for (const auto v : exact.vertices()) {
      // Rounded from the exact value: the lazy kernel's approximation of a point
      // depends on what other threads evaluated, and the output must not.
      const auto& p = exact.point(v);
      points.push_back({{CGAL::to_double(CGAL::exact(p.x())), CGAL::to_double(CGAL::exact(p.y())),
                         CGAL::to_double(CGAL::exact(p.z()))},
                        v});
    }
    std::sort(points.begin(), points.end());
    std::map<ExactMesh::Vertex_index, int> rank;
    std::vector<Double::Vertex_index> added;
    for (std::size_t i = 0; i < points.size(); ++i) {
      rank[points[i].second] = static_cast<int>(i);
      added.push_back(m.add_vertex({points[i].first[0], points[i].first[1], points[i].first[2]}));
    }
    std::vector<std::array<int, 3>> tris;
    for (const auto f : exact.faces()) {
      std::array<int, 3> t{};
      int k = 0;
      for (const auto v : CGAL::vertices_around_face(exact.halfedge(f), exact)) t[static_cast<std::size_t>(k++)] = rank[v];
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());  // keeps the orientation
      tris.push_back(t);
    }
    std::sort(tris.begin(), tris.end());
    for (const auto& t : tris) {
      m.add_face(added[static_cast<std::size_t>(t[0])], added[static_cast<std::size_t>(t[1])], added[static_cast<std::size_t>(t[2])]);
    }
  }
  PMP::experimental::remove_almost_degenerate_faces(m, std::cos(175.0 * M_PI / 180), 100.0, 1e-5);
  m.collect_garbage();
  TriMesh out;
  std::map<Double::Vertex_index, int> index;
  for (const auto v : m.vertices()) {
    const auto& p = m.point(v);
    index[v] = static_cast<int>(out.vertices.size());
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  for (const auto f : m.faces()) {
    std::array<int, 3> tri{};
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(m.halfedge(f), m)) tri[static_cast<std::size_t>(k++)] = index[v];
    out.faces.push_back(tri);
    // The label of the nearest primitive surface to the face's centroid.
    const Vec3 c = (out.vertices[static_cast<std::size_t>(tri[0])] + out.vertices[static_cast<std::size_t>(tri[1])] +
                    out.vertices[static_cast<std::size_t>(tri[2])]) / 3;
    double best = std::numeric_limits<double>::infinity();
    Part part = Part::Berry;
    int berry = -1;
    for (std::size_t i = 0; i < bunch.berries.size(); ++i) {
      const double dist = std::abs((c - bunch.berries[i].centre).norm() - bunch.berries[i].radius);
      if (dist < best) best = dist, part = Part::Berry, berry = static_cast<int>(i);
    }
    for (const Stem& s : bunch.stems) {
      const double dist = stem_surface_distance(s, c);
      if (dist < best) best = dist, part = s.part, berry = -1;
    }
    out.face_part.push_back(part);
    out.face_berry.push_back(berry);
    out.face_internal.push_back(0);
  }
  return out;
}

}  // namespace grapebench
