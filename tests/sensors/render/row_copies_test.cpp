// The rest of the row behind a scene (sensors/render/row_copies.h): copies of the
// vine's foliage along the row and in the rows behind, and trellis posts between vines.
#include "sensors/render/row_copies.h"
#include "synth/generate.h"

#include <gtest/gtest.h>

#include <cmath>

namespace grapebench {
namespace {

struct VineRow {
  Bunch bunch = generate_bunch(preset("table-red"), 11);
  Foliage foliage = generate_foliage(FoliageParams{}, bunch, 3);
};

TEST(RowCopies, SixVinesAlongTheRowAndSevenInTheRowBehindWithoutPostsByDefault) {
  const VineRow r;
  const AppearanceParams a;
  const RowCopies c = row_copies(r.foliage, a, -1.0);
  EXPECT_EQ(c.foliage.triangles.size(), 13 * r.foliage.triangles.size());
  EXPECT_EQ(c.foliage.canes.size(), 13 * r.foliage.canes.size());
  for (const Stem& s : c.foliage.canes) EXPECT_EQ(s.part, Part::Cane);
  EXPECT_TRUE(row_copies(Foliage{}, a, -1.0).foliage.empty());
}

// Posts every `post_every` vines, midway between two, from the ground to above the
// canopy, labelled Background, never beside the scene's own vine.
TEST(RowCopies, PostsStandBetweenVinesFromTheGroundAndNeverBesideTheScenesVine) {
  const VineRow r;
  AppearanceParams a;
  a.post_every = 2;
  const double ground = r.bunch.top.z() - 1.5;
  const RowCopies c = row_copies(r.foliage, a, ground);
  const RowCopies none = row_copies(r.foliage, AppearanceParams{}, ground);
  ASSERT_GT(c.foliage.canes.size(), none.foliage.canes.size());
  double top = -1e9, lo_x = 1e9, hi_x = -1e9;
  for (const Vec3& v : r.foliage.vertices) top = std::max(top, v.z()), lo_x = std::min(lo_x, v.x()), hi_x = std::max(hi_x, v.x());
  for (const Stem& s : r.foliage.canes) {
    top = std::max({top, s.start.z(), s.end.z()});
    lo_x = std::min({lo_x, s.start.x(), s.end.x()}), hi_x = std::max({hi_x, s.start.x(), s.end.x()});
  }
  const double cx = 0.5 * (lo_x + hi_x);  // the vine's middle: leaves and canes
  std::size_t posts = 0;
  for (std::size_t k = none.foliage.canes.size(); k < c.foliage.canes.size(); ++k) {
    const Stem& p = c.foliage.canes[k];
    ++posts;
    EXPECT_EQ(p.part, Part::Background);
    EXPECT_DOUBLE_EQ(p.radius, a.post_radius);
    EXPECT_DOUBLE_EQ(p.start.z(), ground);
    EXPECT_GT(p.end.z(), top);
    EXPECT_EQ(p.start.x(), p.end.x());
    // Midway between vines: x - cx is an odd multiple of half the vine spacing.
    const double k_half = (p.start.x() - cx) / (0.5 * a.vine_spacing);
    EXPECT_NEAR(std::abs(std::fmod(k_half, 2.0)), 1.0, 1e-9);
    const bool own_row = std::abs(p.start.y() - r.bunch.top.y()) < 0.5 * a.row_spacing;
    if (own_row) {
      EXPECT_GT(std::abs(p.start.x() - cx), a.vine_spacing) << "a post beside the scene's vine";
    }
  }
  EXPECT_GE(posts, 4u);
  a.post_every = 0;
  EXPECT_EQ(row_copies(r.foliage, a, ground).foliage.canes.size(), none.foliage.canes.size());
}

}  // namespace
}  // namespace grapebench
