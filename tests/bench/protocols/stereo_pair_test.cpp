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

// A bent main axis is a rachis child of the rachis, as a branch is, but no branch: the
// stalk ends at the first branch even when the bend starts above it (a hand-built
// bunch: the generator bends below the first branch, so only this case can fail).
TEST(StereoPair, ABendIsNoBranchOfTheStalk) {
  Bunch b;
  b.stems.push_back({Vec3(0, 0, -0.003), Vec3(0, 0, 0.04), 0.0035, Part::Peduncle});
  b.peduncle = 0;
  Stem top{Vec3(0, 0, 0), Vec3(0, 0, -0.02), 0.0025, Part::Rachis};
  top.parent = 0;
  b.stems.push_back(top);
  Stem bent{Vec3(0, 0, -0.0195), Vec3(0.01, 0, -0.06), 0.002, Part::Rachis};
  bent.parent = 1;
  b.stems.push_back(bent);
  b.bend = 2;
  const Vec3 on_bent = bent.start + 0.5 * (bent.end - bent.start);
  Stem branch{on_bent, on_bent + Vec3(0.03, 0.01, -0.02), 0.001, Part::Rachis};
  branch.parent = 2;
  b.stems.push_back(branch);
  EXPECT_DOUBLE_EQ(first_branch_height(b), on_bent.z());
}

// The cluster region's rows: the best-scored "bunch" answer, read as the detection
// protocol reads answers (a mask, or a box's pixels), against the truth's cluster
// pixels; a malformed answer fails this estimator's rows instead of the case.
TEST(StereoPair, ClusterRowsScoreTheRegionAgainstTheClusterPixels) {
  StereoTruth t;
  t.width = 10, t.height = 8;
  t.cluster.assign(80, 0);
  for (int v = 3; v <= 6; ++v)
    for (int u = 2; u <= 7; ++u) t.cluster[static_cast<std::size_t>(v) * 10 + u] = 1;  // 24 px
  t.berry_top = 3;
  const auto masked = [](const char* category, double score, int x, int y, int w, int h) {
    ImageDetection d;
    d.category = category, d.score = score;
    d.x = x, d.y = y, d.w = w, d.h = h;
    d.mask_x = x, d.mask_y = y, d.mask_w = w, d.mask_h = h;
    d.mask.assign(static_cast<std::size_t>(w) * h, 1);
    return d;
  };
  Estimate e;
  EXPECT_TRUE(cluster_rows(EstimateRow{}, e, t).empty());  // no region answered: no rows
  e.instances.push_back(masked("berry", 1, 0, 0, 10, 8));
  e.instances.push_back(masked("bunch", 0.2, 0, 0, 10, 8));
  // The scored one: columns 4-9, rows 2-5 (24 px), 12 of them on the cluster (rows
  // 3-5, columns 4-7): IoU 12 / 36.
  e.instances.push_back(masked("bunch", 0.9, 4, 2, 6, 4));
  std::vector<EstimateRow> rows = cluster_rows(EstimateRow{}, e, t);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].quantity, "cluster_iou");
  EXPECT_DOUBLE_EQ(rows[0].estimate, 12.0 / 36.0);
  EXPECT_EQ(rows[0].truth, 1);
  EXPECT_TRUE(rows[0].ok);
  EXPECT_EQ(rows[1].quantity, "cluster_top_px");
  EXPECT_EQ(rows[1].estimate, 2);
  EXPECT_EQ(rows[1].truth, 3);
  EXPECT_TRUE(rows[1].ok);
  // A box without a mask (an external program's answer) is its box's pixels (COCO's
  // pixel u spans [u, u + 1)): the box (2, 3, 6, 4) is columns 2-7, rows 3-6, the
  // cluster exactly.
  ImageDetection& best = e.instances.back();
  best.mask.clear();
  best.x = 2, best.y = 3, best.w = 6, best.h = 4;
  rows = cluster_rows(EstimateRow{}, e, t);
  EXPECT_DOUBLE_EQ(rows[0].estimate, 1.0);
  EXPECT_EQ(rows[1].estimate, 3);
  // An empty mask is an empty region (IoU 0, no top row), not row 0.
  best = masked("bunch", 0.9, 4, 2, 6, 4);
  best.mask.assign(24, 0);
  rows = cluster_rows(EstimateRow{}, e, t);
  EXPECT_EQ(rows[0].estimate, 0);
  EXPECT_TRUE(rows[0].ok);
  EXPECT_FALSE(rows[1].ok);
  // A mask of the wrong length, or off the image: this estimator's rows fail, naming it.
  best.mask.resize(23);
  rows = cluster_rows(EstimateRow{}, e, t);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_FALSE(rows[0].ok);
  EXPECT_NE(rows[0].error.find("instance 2"), std::string::npos) << rows[0].error;
  best = masked("bunch", 0.9, 6, 2, 6, 4);  // columns 6-11 of a 10-column image
  EXPECT_FALSE(cluster_rows(EstimateRow{}, e, t)[0].ok);
}

// The truth behind those rows: the cluster is the bunch below the stalk (berries,
// pedicels, branches; not the peduncle nor the bare rachis above the first branch),
// and berry_top the first row a berry is seen in.
TEST(StereoPair, TheClusterTruthIsTheBunchBelowTheStalk) {
  const Bunch b = generate_bunch(preset("table-red"), 3);
  const double branch_z = first_branch_height(b);
  ScanView view;  // camera at the origin, axes the world's: a pixel's z is its height
  OrganisedCloud& c = view.cloud;
  c.resize(3, 3);
  const auto set = [&](int u, int v, Part part, double z) {
    const std::size_t i = static_cast<std::size_t>(v) * 3 + u;
    c.label[i] = static_cast<std::uint8_t>(part);
    c.valid[i] = 1;
    c.berry[i] = part == Part::Berry ? 0 : -1;
    c.xyz[i] = Eigen::Vector3f(0, 0, static_cast<float>(z));
  };
  for (std::size_t i = 0; i < 9; ++i) c.label[i] = static_cast<std::uint8_t>(Part::None), c.valid[i] = 0;
  set(0, 0, Part::Peduncle, branch_z + 0.02);
  set(1, 0, Part::Rachis, branch_z + 0.01);  // bare stalk
  set(2, 0, Part::Leaf, branch_z);
  set(0, 1, Part::Rachis, branch_z - 0.01);  // a branch's level: cluster
  set(1, 1, Part::Pedicel, branch_z - 0.02);
  set(2, 2, Part::Berry, branch_z - 0.03);
  const StereoTruth t = stereo_truth(view, b, 0.6667);
  const std::vector<std::uint8_t> cluster{0, 0, 0, 1, 1, 0, 0, 0, 1};
  EXPECT_EQ(t.cluster, cluster);
  EXPECT_EQ(t.stalk[0] + t.stalk[1], 2);
  EXPECT_EQ(t.berry_top, 2);
  for (std::size_t i = 0; i < 9; ++i) EXPECT_FALSE(t.cluster[i] && t.stalk[i]) << i;
}

// The oracle ablation's inputs: none unless asked; the truth's cluster pixels; the
// berries redrawn from the label image, white inside, black on every pixel with a
// 4-neighbour of another berry or none (two touching berries stay apart).
TEST(StereoPair, TheOracleGivesTheExactClusterAndTheBerriesOutlines) {
  ScanView view;
  OrganisedCloud& c = view.cloud;
  c.resize(8, 5);
  for (std::size_t i = 0; i < c.size(); ++i) c.label[i] = static_cast<std::uint8_t>(Part::Leaf), c.berry[i] = -1;
  for (int v = 0; v < 5; ++v)
    for (int u = 1; u < 7; ++u) {  // berry 3 on columns 1-3, berry 4 on columns 4-6
      const std::size_t i = static_cast<std::size_t>(v) * 8 + u;
      c.label[i] = static_cast<std::uint8_t>(Part::Berry);
      c.berry[i] = u < 4 ? 3 : 4;
    }
  StereoTruth t;
  t.width = 8, t.height = 5;
  t.cluster.assign(40, 0);
  t.cluster[17] = 1;
  using O = PipelineSpec::Oracle;
  EXPECT_EQ(stereo_oracle(O::None, view, t), nullptr);
  const auto cluster = stereo_oracle(O::Cluster, view, t);
  ASSERT_NE(cluster, nullptr);
  EXPECT_EQ(cluster->cluster, t.cluster);
  EXPECT_TRUE(cluster->berry_edges.data.empty());
  const auto berries = stereo_oracle(O::Berries, view, t);
  EXPECT_TRUE(berries->cluster.empty());
  ASSERT_EQ(berries->berry_edges.width, 8);
  ASSERT_EQ(berries->berry_edges.data.size(), 120u);
  // White: rows 1-3 of columns 2 and 5 only (the rest touch the image's edge, a leaf or
  // the other berry).
  for (int v = 0; v < 5; ++v)
    for (int u = 0; u < 8; ++u) {
      const bool white = v >= 1 && v <= 3 && (u == 2 || u == 5);
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_EQ(berries->berry_edges.data[3 * (static_cast<std::size_t>(v) * 8 + u) + ch], white ? 255 : 0)
            << u << ", " << v;
    }
  const auto both = stereo_oracle(O::Both, view, t);
  EXPECT_EQ(both->cluster, t.cluster);
  EXPECT_EQ(both->berry_edges.data, berries->berry_edges.data);
}

}  // namespace
}  // namespace grapebench
