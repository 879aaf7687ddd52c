// The vine-row scene: leaves and canes around a bunch (synth/foliage.h), seen by the
// ray scene with their own labels and colours.
#include "sensors/d435.h"
#include "sensors/ray_scene.h"
#include "sensors/rig.h"
#include "synth/foliage.h"
#include "synth/generate.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

namespace grapebench {
namespace {

TEST(Foliage, LeavesKeepTheirClearanceAndTheSeedFixesThem) {
  const Bunch b = generate_bunch(preset("table-red"), 11);
  FoliageParams p;
  p.clearance = 0.01;
  const Foliage f = generate_foliage(p, b, 3);
  EXPECT_EQ(f.triangles.size(), static_cast<std::size_t>(24 * p.leaves));
  EXPECT_EQ(f.canes.size(), static_cast<std::size_t>(1 + p.shoots));
  // Every leaf point (outline and centre) stays outside every berry by the clearance.
  for (const Vec3& v : f.vertices) {
    for (const auto& be : b.berries) ASSERT_GE((v - be.centre).norm() - be.radius, p.clearance - 1e-9);
  }
  const Foliage again = generate_foliage(p, b, 3);
  ASSERT_EQ(again.vertices.size(), f.vertices.size());
  for (std::size_t i = 0; i < f.vertices.size(); ++i) ASSERT_EQ(again.vertices[i], f.vertices[i]);
  EXPECT_NE(generate_foliage(p, b, 4).vertices.front(), f.vertices.front());
}

// A seed names one row whatever compiled the generator: leaf centres, tilts and cane
// leans were drawn in a call's arguments, whose order GCC and clang take differently
// (clang's builds grew other rows). Now each draw is its own statement; the bits were
// GCC's. FNV-1a over the vertices' and canes' doubles.
TEST(Foliage, ASeedGivesTheSameBitsOnEveryCompiler) {
  const Foliage f = generate_foliage(FoliageParams{}, generate_bunch(preset("table-red"), 11), 3);
  std::uint64_t h = 0xcbf29ce484222325ULL;
  const auto mix = [&h](double v) {
    unsigned char bytes[sizeof v];
    std::memcpy(bytes, &v, sizeof v);
    for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ULL;
  };
  for (const Vec3& v : f.vertices)
    for (int a = 0; a < 3; ++a) mix(v[a]);
  for (const auto& c : f.canes)
    for (int a = 0; a < 3; ++a) mix(c.end[a]);
  EXPECT_EQ(h, 18090800119252644983ULL);
}

TEST(Foliage, RaysReturnLeafAndCaneLabelsWithTheirColours) {
  const Bunch b = generate_bunch(preset("table-red"), 11);
  const Foliage f = generate_foliage(FoliageParams{}, b, 3);
  const RayScene scene(b, std::nullopt, f);
  // A ray along the normal at a point inside the first leaf triangle.
  const Vec3 a = f.vertices[0], bb = f.vertices[1], cc = f.vertices[2];
  const Vec3 n = (bb - a).cross(cc - a).normalized();
  const Vec3 c = 0.5 * a + 0.25 * bb + 0.25 * cc;
  const Hit h = scene.intersect(Ray{c + 0.002 * n, -n});
  ASSERT_TRUE(h.valid());
  EXPECT_EQ(h.part, Part::Leaf);
  EXPECT_NEAR(h.t, 0.002, 1e-12);  // refined in double against the triangle's plane
  EXPECT_EQ(h.colour.g, f.triangle_colour[0].g);
  // The cordon, hit from the front.
  const Stem& cordon = f.canes[0];
  const Vec3 mid = 0.5 * (cordon.start + cordon.end);
  const Hit hc = scene.intersect(Ray{mid - Vec3(0, 2, 0), Vec3::UnitY()});
  ASSERT_TRUE(hc.valid());
  EXPECT_TRUE(hc.part == Part::Cane || hc.part == Part::Leaf || hc.part <= Part::Peduncle);
  // A D435 frame of the row sees leaves, canes and the bunch, each labelled.
  const D435 d435(D435Params{});
  const auto rig = make_robot_pass(RobotPassParams{});
  const auto views = rig->views(scene.bunch_centre(), scene.bunch_radius(), BackgroundSpec{});
  const OrganisedCloud frame = d435.capture(scene, views[views.size() / 2].pose, 1);
  std::size_t leaf = 0, cane = 0, berry = 0;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    if (!frame.valid[i]) continue;
    leaf += frame.label[i] == static_cast<std::uint8_t>(Part::Leaf);
    cane += frame.label[i] == static_cast<std::uint8_t>(Part::Cane);
    berry += frame.label[i] == static_cast<std::uint8_t>(Part::Berry);
  }
  EXPECT_GT(leaf, 1000u);
  EXPECT_GT(cane, 50u);
  EXPECT_GT(berry, 300u);
}

// The trellis wires (issue 38, item 6): a pair per `wire_pairs` above the cordon on
// both faces of the canopy, labelled Background in the exact scene (so no image shows
// a wire where the labels say leaf), in the trellis colour; the leaves are the same
// with and without them (the wires draw nothing from the seed).
TEST(Foliage, WiresRunAboveTheCordonLabelledBackgroundAndLeaveTheLeavesAlone) {
  const Bunch b = generate_bunch(preset("table-red"), 11);
  FoliageParams p;
  p.wire_pairs = 2;
  const Foliage f = generate_foliage(p, b, 3);
  const Foliage plain = generate_foliage(FoliageParams{}, b, 3);
  ASSERT_EQ(f.canes.size(), plain.canes.size() + 4);
  EXPECT_EQ(f.vertices, plain.vertices);
  const Stem& cordon = f.canes[0];
  std::vector<Stem> wires(f.canes.end() - 4, f.canes.end());
  for (std::size_t k = 0; k < wires.size(); ++k) {
    const Stem& w = wires[k];
    EXPECT_EQ(w.part, Part::Background);
    EXPECT_DOUBLE_EQ(w.radius, p.wire_radius);
    EXPECT_NEAR(w.start.z() - cordon.start.z(), (1 + static_cast<int>(k / 2)) * p.wire_spacing, 1e-12);
    EXPECT_NEAR(std::abs(w.start.y() - cordon.start.y()), 0.5 * p.canopy_depth, 1e-12);
    EXPECT_NEAR((w.end - w.start).x(), 2 * p.row_half_length, 1e-12);
  }
  // A ray onto the lower front wire's middle returns it, labelled and coloured.
  const RayScene scene(b, std::nullopt, f);
  const Vec3 mid = 0.5 * (wires[0].start + wires[0].end);
  const Hit h = scene.intersect(Ray{Vec3(mid.x(), mid.y() - 2, mid.z()), Vec3::UnitY()});
  ASSERT_TRUE(h.valid());
  if (h.part == Part::Background) {
    EXPECT_NEAR(h.t, 2 - p.wire_radius, 1e-9);
    EXPECT_EQ(h.colour.r, p.trellis_colour.r);
  } else {
    EXPECT_EQ(h.part, Part::Leaf);  // a leaf in front of the wire
  }
  // Somewhere along the wire it is seen: sweep x.
  std::size_t seen = 0;
  for (int i = 0; i <= 100; ++i) {
    const Vec3 at = wires[0].start + (i / 100.0) * (wires[0].end - wires[0].start);
    const Hit hw = scene.intersect(Ray{Vec3(at.x(), at.y() - 2, at.z()), Vec3::UnitY()});
    seen += hw.valid() && hw.part == Part::Background;
  }
  EXPECT_GT(seen, 20u);
}

}  // namespace
}  // namespace grapebench
