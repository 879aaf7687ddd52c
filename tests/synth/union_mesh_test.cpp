// synth/union_mesh: the bunch's surface is one closed, outward, self-intersection-free
// mesh whose enclosed volume is the exact solid's.
#include "synth/union_mesh.h"

#include "synth/generate.h"
#include "synth/ground_truth.h"
#include "synth/params.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

namespace grapebench {
namespace {

Bunch small_bunch(const char* name, std::uint64_t seed, int berries) {
  BunchParams p = preset(name);
  p.berry_count_min = p.berry_count_max = berries;
  return generate_bunch(p, seed);
}

// Every directed edge once, and its reverse once: closed, manifold along edges and
// consistently oriented.
void expect_closed_and_oriented(const TriMesh& m) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& f : m.faces) {
    for (int k = 0; k < 3; ++k) ++directed[{f[static_cast<std::size_t>(k)], f[static_cast<std::size_t>((k + 1) % 3)]}];
  }
  int bad = 0;
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    bad += count != 1 || reverse == directed.end() || reverse->second != 1;
  }
  EXPECT_EQ(bad, 0) << "directed edges without exactly one opposite";
}

bool self_intersects(const TriMesh& m) {
  using Mesh = CGAL::Surface_mesh<CGAL::Exact_predicates_inexact_constructions_kernel::Point_3>;
  Mesh s;
  std::vector<Mesh::Vertex_index> v;
  for (const Vec3& p : m.vertices) v.push_back(s.add_vertex({p.x(), p.y(), p.z()}));
  for (const auto& f : m.faces) s.add_face(v[static_cast<std::size_t>(f[0])], v[static_cast<std::size_t>(f[1])], v[static_cast<std::size_t>(f[2])]);
  return CGAL::Polygon_mesh_processing::does_self_intersect(s);
}

TEST(UnionMesh, ClosedOutwardAndWithoutSelfIntersectionForEveryPreset) {
  for (const char* name : {"table-red", "wine-red", "summer-black", "green-table"}) {
    const Bunch b = small_bunch(name, 3, 30);
    const TriMesh m = bunch_surface(b);
    SCOPED_TRACE(name);
    expect_closed_and_oriented(m);
    EXPECT_FALSE(self_intersects(m));
    const double exact = solid_volume_terms(b).solid, volume = enclosed_volume(m);
    EXPECT_GT(volume, 0);  // outward: positive signed volume
    EXPECT_LT(std::abs(volume / exact - 1), 0.005) << volume << " vs " << exact;
    std::printf("[union mesh] %s, 30 berries: %zu triangles, volume error %+.4f %%\n", name, m.faces.size(),
                100 * (volume / exact - 1));
  }
}

// The pieces are scaled to their exact volumes, so the error left is where pieces
// meet; it shrinks as the tessellation refines.
TEST(UnionMesh, VolumeConvergesToTheExactSolid) {
  const Bunch b = small_bunch("wine-red", 5, 40);
  const double exact = solid_volume_terms(b).solid;
  double coarse = 0, fine = 0;
  // Levels 0-2 (measured 7.1e-4, 6.7e-5, 7.2e-6; level 3 3.1e-7 took 70 % of the
  // test's time, 74 s under ASan).
  for (int level = 0; level <= 2; ++level) {
    MeshOptions o;
    o.sphere_subdivisions = level;
    o.tube_sides = 6 << level;
    const double err = std::abs(enclosed_volume(bunch_surface(b, o)) / exact - 1);
    std::printf("[union mesh] level %d, %d-sided tubes: relative volume error %.2e\n", level, o.tube_sides, err);
    if (level == 0) coarse = err;
    fine = err;
  }
  EXPECT_LT(fine, coarse / 20);
  EXPECT_LT(fine, 2e-5);
}

TEST(UnionMesh, FacesCarryTheirPartAndBerry) {
  const Bunch b = small_bunch("table-red", 2, 25);
  const TriMesh m = bunch_surface(b);
  std::map<Part, int> parts;
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    ++parts[m.face_part[f]];
    if (m.face_part[f] == Part::Berry) {
      EXPECT_GE(m.face_berry[f], 0);
    }
  }
  for (const Part p : {Part::Berry, Part::Pedicel, Part::Rachis, Part::Peduncle}) EXPECT_GT(parts[p], 0);
}

}  // namespace
}  // namespace grapebench
