#include "bench/protocols/stereo_pair.h"

#include <gtest/gtest.h>

#include "synth/generate.h"
#include "synth/params.h"

namespace grapebench {
namespace {

// The stalk ends at the main body's first branch. A wing's side branches leave the
// wing near the peduncle, above it, and must not lift the stalk's lower end: the
// wing draws from its own stream, so the same seed gives the same main skeleton with
// and without it (found in review: they did lift it, labelling the bare rachis bunch).
TEST(StereoPair, AWingDoesNotMoveTheStalksLowerEnd) {
  BunchParams p = preset("table-red");
  int winged = 0;
  for (std::uint64_t seed = 0; seed < 2; ++seed) {
    p.wing_probability = 0;
    const double without = first_branch_height(generate_bunch(p, seed));
    p.wing_probability = 1;
    const Bunch b = generate_bunch(p, seed);
    if (b.wing < 0) continue;
    ++winged;
    // Its side branches start above the body's first branch, so the test can fail.
    double highest = -1;
    for (std::size_t i = 0; i < b.stems.size(); ++i) {
      if (b.stems[i].parent == b.wing && b.stems[i].part == Part::Rachis) highest = std::max(highest, b.stems[i].start.z());
    }
    EXPECT_GT(highest, without) << "seed " << seed;
    EXPECT_EQ(first_branch_height(b), without) << "seed " << seed;
    EXPECT_TRUE(on_wing(b, b.wing));
    EXPECT_FALSE(on_wing(b, b.peduncle));
  }
  EXPECT_EQ(winged, 2);
}

// The cluster region's rows: its mask against the truth's cluster pixels, its top row
// against the topmost berry's; the best-scored "bunch" instance only; mask pixels off
// the image count for neither side.
TEST(StereoPair, ClusterRowsScoreTheRegionAgainstTheClusterPixels) {
  StereoTruth t;
  t.width = 10, t.height = 8;
  t.cluster.assign(80, 0);
  for (int v = 3; v <= 6; ++v)
    for (int u = 2; u <= 7; ++u) t.cluster[static_cast<std::size_t>(v) * 10 + u] = 1;  // 24 px
  t.berry_top = 3;
  const auto box = [](const char* category, double score, int x, int y, int w, int h) {
    ImageDetection d;
    d.category = category, d.score = score;
    d.mask_x = x, d.mask_y = y, d.mask_w = w, d.mask_h = h;
    d.mask.assign(static_cast<std::size_t>(w) * h, 1);
    return d;
  };
  Estimate e;
  EXPECT_TRUE(cluster_rows(EstimateRow{}, e, t).empty());  // no region answered: no rows
  e.instances.push_back(box("berry", 1, 0, 0, 10, 8));
  e.instances.push_back(box("bunch", 0.2, 0, 0, 10, 8));
  // The scored one: columns 4-11 (10 and 11 off the image), rows 2-5: 24 px on the image,
  // 12 of them on the cluster (rows 3-5, columns 4-7): IoU 12 / 36.
  e.instances.push_back(box("bunch", 0.9, 4, 2, 8, 4));
  const std::vector<EstimateRow> rows = cluster_rows(EstimateRow{}, e, t);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].quantity, "cluster_iou");
  EXPECT_DOUBLE_EQ(rows[0].estimate, 12.0 / 36.0);
  EXPECT_EQ(rows[0].truth, 1);
  EXPECT_TRUE(rows[0].ok);
  EXPECT_EQ(rows[1].quantity, "cluster_top_px");
  EXPECT_EQ(rows[1].estimate, 2);
  EXPECT_EQ(rows[1].truth, 3);
  EXPECT_TRUE(rows[1].ok);
  // An empty mask is an empty region, not row 0; a mask of the wrong size is refused.
  e.instances.back().mask.assign(32, 0);
  const std::vector<EstimateRow> empty = cluster_rows(EstimateRow{}, e, t);
  EXPECT_EQ(empty[0].estimate, 0);
  EXPECT_FALSE(empty[1].ok);
  e.instances.back().mask.resize(31);
  EXPECT_THROW(cluster_rows(EstimateRow{}, e, t), InputError);
}

}  // namespace
}  // namespace grapebench
