#include "synth/mesh.h"

#include "synth/generate.h"
#include "synth/ground_truth.h"
#include "synth/params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace grapebench {
namespace {

// The mesh's pieces are closed and disjoint, so its enclosed volume converges to
// the analytic volume (inscribed tessellation: error ~ h^2, a factor ~4 per level).
TEST(Mesh, EnclosedVolumeConvergesToAnalyticVolume) {
  BunchParams p = preset("wine-red");
  p.berry_count_min = p.berry_count_max = 40;
  const Bunch b = generate_bunch(p, 5);
  const double exact = solid_volume_terms(b).solid;
  double previous = 1;
  for (int level = 1; level <= 4; ++level) {
    MeshOptions o;
    o.sphere_subdivisions = level;
    o.tube_sides = 6 << level;
    const double err = std::abs(enclosed_volume(bunch_mesh(b, o)) / exact - 1);
    std::printf("[mesh] level %d (%d triangles per berry, %d-sided tubes): relative volume error %.2e\n", level,
                20 << (2 * level), o.tube_sides, err);
    EXPECT_LT(err, previous * 0.35) << "level " << level << ": expected second-order convergence";
    previous = err;
  }
  EXPECT_LT(previous, 3e-3);
}

TEST(Mesh, LabelsAndExport) {
  const Bunch b = generate_bunch(preset("table-red"), 2);
  const TriMesh m = bunch_mesh(b);
  ASSERT_EQ(m.faces.size(), m.face_part.size());
  int berry_faces = 0, stem_faces = 0;
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    if (m.face_internal[f]) continue;
    if (m.face_part[f] == Part::Berry) {
      ++berry_faces;
      EXPECT_GE(m.face_berry[f], 0);
    } else {
      ++stem_faces;
    }
  }
  EXPECT_GT(berry_faces, 0);
  EXPECT_GT(stem_faces, 0);
  const std::string ply = ply_bytes(m);
  EXPECT_EQ(ply.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
  EXPECT_NE(ply.find("property uchar part"), std::string::npos);
  const std::string obj = obj_text(m, "parts.mtl");
  EXPECT_NE(obj.find("usemtl peduncle"), std::string::npos);
  EXPECT_NE(obj.find("g berry_0"), std::string::npos);
}

}  // namespace
}  // namespace grapebench
