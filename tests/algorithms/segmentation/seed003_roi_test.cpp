// Seed 003's colour and spatial steps: NDI (Eq. 1), seeded k-means++, Euclidean
// clusters, automatic detection, ROI_CM (Eq. 2) and fine tuning, on a synthetic
// coloured frame whose grape points are known.
#include "algorithms/segmentation/seed003_roi.h"
#include "synth/config.h"
#include "synth/rng.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace grapebench {
namespace {

TEST(Ndi, ChannelsFollowEquationOneAndBlackIsZero) {
  const Vec3 red = ndi(Rgb8{255, 0, 0});
  EXPECT_DOUBLE_EQ(red.x(), 1.0);
  EXPECT_DOUBLE_EQ(red.y(), 1.0);
  EXPECT_DOUBLE_EQ(red.z(), 0.0);  // B + G = 0: no contrast
  const Vec3 c = ndi(Rgb8{150, 30, 60});
  EXPECT_DOUBLE_EQ(c.x(), 120.0 / 180.0);
  EXPECT_DOUBLE_EQ(c.y(), 90.0 / 210.0);
  EXPECT_DOUBLE_EQ(c.z(), 30.0 / 90.0);
  for (int r = 0; r < 256; r += 51) {
    for (int g = 0; g < 256; g += 51) {
      for (int b = 0; b < 256; b += 51) {
        const Vec3 v = ndi(Rgb8{static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g), static_cast<std::uint8_t>(b)});
        ASSERT_TRUE(v.allFinite()) << r << " " << g << " " << b;
        ASSERT_LE(v.cwiseAbs().maxCoeff(), 1.0);
      }
    }
  }
  EXPECT_EQ(ndi(Rgb8{0, 0, 0}), Vec3::Zero());
}

std::vector<Vec3> blobs(std::uint64_t seed, std::vector<int>& truth) {
  Rng rng(seed);
  const Vec3 centres[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0.5}};
  std::vector<Vec3> x;
  truth.clear();
  for (int c = 0; c < 3; ++c) {
    for (int i = 0; i < 200 + 50 * c; ++i) {
      x.push_back(centres[c] + 0.05 * Vec3(rng.normal(), rng.normal(), rng.normal()));
      truth.push_back(c);
    }
  }
  return x;
}

TEST(KMeansPlusPlus, SeededRunsAreIdenticalAndRecoverSeparatedBlobs) {
  std::vector<int> truth;
  const auto x = blobs(3, truth);
  const KMeansResult a = kmeans_pp(x, {3, 100, 11}), b = kmeans_pp(x, {3, 100, 11});
  EXPECT_EQ(a.label, b.label);
  ASSERT_EQ(a.centroids.size(), 3u);
  for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(a.centroids[c], b.centroids[c]);
  EXPECT_TRUE(a.converged);
  // The partition is the true one, up to the cluster numbering.
  std::set<std::pair<int, int>> pairs;
  for (std::size_t i = 0; i < x.size(); ++i) pairs.insert({truth[i], a.label[i]});
  EXPECT_EQ(pairs.size(), 3u);
  EXPECT_EQ(a.sizes[static_cast<std::size_t>(a.label[0])], 200u);
  // Other seeds find the same partition on such blobs.
  for (std::uint64_t s = 1; s < 6; ++s) {
    const KMeansResult r = kmeans_pp(x, {3, 100, s});
    std::set<std::pair<int, int>> q;
    for (std::size_t i = 0; i < x.size(); ++i) q.insert({truth[i], r.label[i]});
    EXPECT_EQ(q.size(), 3u) << "seed " << s;
  }
}

TEST(KMeansPlusPlus, DuplicatePointsAndBadInputAreHandled) {
  const std::vector<Vec3> same(10, Vec3(1, 2, 3));
  const KMeansResult r = kmeans_pp(same, {3, 100, 1});
  for (const auto& c : r.centroids) EXPECT_TRUE(c.allFinite());
  EXPECT_DOUBLE_EQ(r.inertia, 0.0);
  EXPECT_THROW(kmeans_pp(same, {11, 100, 1}), InputError);
  EXPECT_THROW(kmeans_pp(same, {0, 100, 1}), InputError);
  std::vector<Vec3> bad = same;
  bad[4].x() = NAN;
  EXPECT_THROW(kmeans_pp(bad, {3, 100, 1}), InputError);
}

// A frame: a red grape cluster (sphere of 6 cm at 1 m), green leaves behind and beside
// it, a brown cane, and a small red blob of 100 points (a false positive to drop).
struct Frame {
  PointCloud cloud;
  std::vector<Rgb8> rgb;
  std::vector<char> grape;  // truth: the rows of the cluster
};

Frame coloured_frame(std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Vec3> p;
  Frame f;
  auto colour = [&](int r, int g, int b) {
    auto jitter = [&](int v) { return static_cast<std::uint8_t>(std::clamp(v + rng.uniform_int(-12, 12), 0, 255)); };
    f.rgb.push_back({jitter(r), jitter(g), jitter(b)});
  };
  // Grape cluster: the camera-facing half of a 6 cm sphere, 3000 points.
  for (int i = 0; i < 3000; ++i) {
    Vec3 d(rng.normal(), rng.normal(), rng.normal());
    d.normalize();
    if (d.z() > 0) d.z() = -d.z();
    p.push_back(Vec3(0, 0, 1) + 0.06 * d);
    colour(150, 30, 60);
    f.grape.push_back(1);
  }
  // Leaves: a 0.5 x 0.5 m patch 10 cm behind the cluster, 6000 points.
  for (int i = 0; i < 6000; ++i) {
    p.push_back(Vec3(rng.uniform(-0.25, 0.25), rng.uniform(-0.25, 0.25), 1.10));
    colour(60, 130, 40);
    f.grape.push_back(0);
  }
  // A cane: a brown line of points above.
  for (int i = 0; i < 800; ++i) {
    p.push_back(Vec3(rng.uniform(-0.3, 0.3), -0.2 + 0.005 * rng.normal(), 1.0));
    colour(110, 80, 50);
    f.grape.push_back(0);
  }
  // A small red blob (100 points) far from the cluster.
  for (int i = 0; i < 100; ++i) {
    p.push_back(Vec3(0.2, 0.2, 1.0) + 0.01 * Vec3(rng.normal(), rng.normal(), rng.normal()));
    colour(150, 30, 60);
    f.grape.push_back(0);
  }
  f.cloud = to_point_cloud(p);
  return f;
}

TEST(Seed003Roi, DetectionFindsTheClusterAndDropsSmallFalsePositives) {
  const Frame f = coloured_frame(5);
  const Seed003Detection d = detect_grape_regions(f.cloud, f.rgb, {});
  ASSERT_EQ(d.regions.size(), 1u) << d.notes;
  std::size_t hit = 0, grapes = 0;
  for (auto i : d.regions[0]) hit += f.grape[static_cast<std::size_t>(i)];
  for (char g : f.grape) grapes += g;
  EXPECT_EQ(hit, d.regions[0].size()) << "precision";
  EXPECT_GE(static_cast<double>(hit) / grapes, 0.99) << "recall";
  // Deterministic.
  EXPECT_EQ(detect_grape_regions(f.cloud, f.rgb, {}).regions, d.regions);
}

TEST(Seed003Roi, CentreOfMassBoxAndFineTuningRecoverTheCluster) {
  const Frame f = coloured_frame(6);
  Region rough;  // the manual path: the truth's rows
  for (std::size_t i = 0; i < f.grape.size(); ++i) {
    if (f.grape[i]) rough.push_back(static_cast<Eigen::Index>(i));
  }
  const Region cm = roi_from_centre_of_mass(f.cloud, rough, 0.15);
  // Eq. 2 by brute force: centre of mass of the rough rows, strict box.
  Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
  for (auto i : rough) c += f.cloud.row(i);
  c /= static_cast<double>(rough.size());
  std::size_t expected = 0;
  for (Eigen::Index i = 0; i < f.cloud.rows(); ++i) expected += (f.cloud.row(i) - c).cwiseAbs().maxCoeff() < 0.15;
  EXPECT_EQ(cm.size(), expected);
  EXPECT_GT(cm.size(), rough.size());  // leaves came in with the box
  const Region tuned = fine_tune_region(f.cloud, f.rgb, cm, {});
  std::size_t hit = 0;
  for (auto i : tuned) hit += f.grape[static_cast<std::size_t>(i)];
  EXPECT_EQ(hit, tuned.size());
  EXPECT_GE(static_cast<double>(hit) / rough.size(), 0.99);
  EXPECT_THROW(roi_from_centre_of_mass(f.cloud, rough, 0), InputError);
  EXPECT_THROW(detect_grape_regions(f.cloud, std::vector<Rgb8>(3), {}), InputError);
}

TEST(EuclideanClusters, SeparateGroupsAndDropSmallOnes) {
  std::vector<Vec3> p;
  for (int i = 0; i < 400; ++i) p.push_back(Vec3(0.001 * i, 0, 0));        // 0.4 m line, 1 mm steps
  for (int i = 0; i < 350; ++i) p.push_back(Vec3(0.001 * i, 0.5, 0));      // another
  for (int i = 0; i < 50; ++i) p.push_back(Vec3(0.001 * i, -0.5, 0));      // too small
  const auto c = euclidean_clusters(to_point_cloud(p), {});
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].size(), 400u);
  EXPECT_EQ(c[1].size(), 350u);
  EXPECT_EQ(c[1].front(), 400);
}

}  // namespace
}  // namespace grapebench
