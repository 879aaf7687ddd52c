// Pipeline steps (algorithms/cloud/filters.h) on synthetic clouds with known answers and on
// scans whose ground-truth labels score them.
#include "algorithms/cloud/filters.h"
#include "sensors/ideal.h"
#include "sensors/kinect_v2.h"
#include "sensors/scan.h"
#include "synth/generate.h"
#include "synth/rng.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace grapebench {
namespace {

PointCloud sphere_samples(int n, double r, std::uint64_t seed) {
  Rng rng(seed);
  PointCloud c(n, 3);
  for (int i = 0; i < n; ++i) {
    Vec3 v(rng.normal(), rng.normal(), rng.normal());
    c.row(i) = r * v.normalized().transpose();
  }
  return c;
}

// Returns and labels of one view (all valid returns: no segmentation).
struct LabelledView {
  PointCloud points;
  std::vector<std::uint8_t> labels;
};
std::vector<LabelledView> labelled_views(const Sensor& sensor, int views, const BackgroundSpec& bg) {
  const Bunch b = generate_bunch(preset("table-red"), 21);
  const RayScene scene(b);
  TurntableParams tp;
  tp.views = views;
  tp.step_deg = 360.0 / views;
  const Scan scan = scan_bunch(scene, sensor, *make_turntable(tp), bg, 4);
  std::vector<LabelledView> out;
  for (const auto& v : scan.views) {
    std::vector<Vec3> pts;
    LabelledView lv;
    for (std::size_t i = 0; i < v.cloud.size(); ++i) {
      if (!v.cloud.valid[i]) continue;
      pts.push_back(v.rig.pose * v.cloud.xyz[i].cast<double>());
      lv.labels.push_back(v.cloud.label[i]);
    }
    lv.points = to_point_cloud(pts);
    out.push_back(std::move(lv));
  }
  return out;
}

bool is_bunch(std::uint8_t l) { return l <= static_cast<std::uint8_t>(Part::Peduncle); }

TEST(PassThrough, KeepsExactlyThePointsInTheBox) {
  const PointCloud c = sphere_samples(2000, 0.05, 1);
  PassThroughParams p;
  p.min = Vec3(-0.02, -1, -1);
  p.max = Vec3(0.03, 1, 0.01);
  const FilteredCloud f = pass_through(c, p);
  std::size_t expected = 0;
  for (Eigen::Index i = 0; i < c.rows(); ++i) expected += c(i, 0) >= -0.02 && c(i, 0) <= 0.03 && c(i, 2) <= 0.01;
  ASSERT_EQ(static_cast<std::size_t>(f.points.rows()), expected);
  for (Eigen::Index i = 0; i < f.points.rows(); ++i) EXPECT_EQ(f.points.row(i), c.row(f.source[static_cast<std::size_t>(i)]));
  p.max.x() = -0.03;
  EXPECT_THROW(pass_through(c, p), InputError);
}

TEST(StatisticalOutlierRemoval, DropsFarPointsAndKeepsTheSurface) {
  PointCloud c = sphere_samples(5000, 0.05, 2);
  PointCloud noisy(c.rows() + 50, 3);
  noisy.topRows(c.rows()) = c;
  Rng rng(3);
  for (int i = 0; i < 50; ++i) noisy.row(c.rows() + i) = 0.2 * Vec3(rng.normal(), rng.normal(), rng.normal()).transpose();
  const FilteredCloud f = statistical_outlier_removal(noisy, {});
  std::size_t outliers_kept = 0, surface_kept = 0;
  for (auto s : f.source) (s >= c.rows() ? outliers_kept : surface_kept)++;
  EXPECT_EQ(outliers_kept, 0u);
  EXPECT_GT(surface_kept, 0.85 * 5000);
  EXPECT_THROW(statistical_outlier_removal(noisy, {0, 1.0}), InputError);
}

TEST(VoxelGrid, OnePointPerOccupiedVoxelAtItsCentroid) {
  const PointCloud c = sphere_samples(20000, 0.05, 4);
  for (const double leaf : {0.01, 0.0013}) {  // a dense grid, and one sparse beside the cloud (sorted)
    const FilteredCloud f = voxel_grid(c, {leaf});
    // Open3D's grid: from half a leaf below the smallest coordinates.
    const Eigen::RowVector3d lo = c.colwise().minCoeff().array() - 0.5 * leaf;
    std::map<std::array<long, 3>, std::vector<Eigen::Index>> cells;
    for (Eigen::Index i = 0; i < c.rows(); ++i) {
      const Eigen::RowVector3d q = (c.row(i) - lo) / leaf;
      cells[{static_cast<long>(std::floor(q(2))), static_cast<long>(std::floor(q(1))), static_cast<long>(std::floor(q(0)))}]
          .push_back(i);
    }
    ASSERT_EQ(f.points.rows(), static_cast<Eigen::Index>(cells.size()));
    Eigen::Index k = 0;
    for (const auto& [key, rows] : cells) {  // z, y, x: the output's order
      Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
      for (auto i : rows) sum += c.row(i);
      EXPECT_LT((f.points.row(k) - sum / static_cast<double>(rows.size())).norm(), 1e-12);
      EXPECT_NE(std::find(rows.begin(), rows.end(), f.source[static_cast<std::size_t>(k)]), rows.end());
      ++k;
    }
  }
  EXPECT_THROW(voxel_grid(c, {0}), InputError);
}

TEST(RegionGrowing, SeparatesTheBunchFromThePlateInAKinectView) {
  BackgroundSpec plate;
  plate.type = BackgroundType::Plate;
  const auto views = labelled_views(KinectV2(KinectV2Params{}), 1, plate);
  const LabelledView& v = views[0];
  const FilteredCloud f = region_growing_segmentation(v.points, {});
  std::size_t bunch = 0, kept = 0, kept_bunch = 0;
  for (auto l : v.labels) bunch += is_bunch(l);
  for (auto s : f.source) {
    ++kept;
    kept_bunch += is_bunch(v.labels[static_cast<std::size_t>(s)]);
  }
  const double precision = static_cast<double>(kept_bunch) / static_cast<double>(kept);
  const double recall = static_cast<double>(kept_bunch) / static_cast<double>(bunch);
  std::printf("region growing: %zu returns, %zu bunch; precision %.4f recall %.4f (%s)\n", static_cast<std::size_t>(v.points.rows()),
              bunch, precision, recall, f.notes.c_str());
  EXPECT_GT(precision, 0.98);
  EXPECT_GT(recall, 0.9);
}

TEST(LccpStalkRemoval, RemovesThePeduncleAndKeepsTheBody) {
  std::vector<Vec3> pts;
  std::vector<std::uint8_t> labels;
  for (const auto& v : labelled_views(IdealSensor(IdealParams{}), 8, BackgroundSpec{})) {
    for (Eigen::Index i = 0; i < v.points.rows(); ++i) {
      if (!is_bunch(v.labels[static_cast<std::size_t>(i)])) continue;
      pts.push_back(v.points.row(i).transpose());
      labels.push_back(v.labels[static_cast<std::size_t>(i)]);
    }
  }
  const PointCloud c = to_point_cloud(pts);
  const FilteredCloud f = lccp_stalk_removal(c, {});
  const auto peduncle = static_cast<std::uint8_t>(Part::Peduncle);
  double ped = 0, body = 0, ped_kept = 0, body_kept = 0;
  for (auto l : labels) (l == peduncle ? ped : body) += 1;
  for (auto s : f.source) (labels[static_cast<std::size_t>(s)] == peduncle ? ped_kept : body_kept) += 1;
  std::printf("lccp: peduncle kept %.3f, body kept %.4f (%s)\n", ped_kept / ped, body_kept / body, f.notes.c_str());
  EXPECT_LT(ped_kept / ped, 0.05);
  EXPECT_GT(body_kept / body, 0.98);
}

TEST(Filters, DegenerateInputIsAnError) {
  const PointCloud empty(0, 3);
  EXPECT_THROW(statistical_outlier_removal(empty, {}), InputError);
  EXPECT_THROW(region_growing_segmentation(empty, {}), InputError);
  EXPECT_THROW(lccp_stalk_removal(empty, {}), InputError);
  PointCloud nan = sphere_samples(100, 0.05, 5);
  nan(7, 1) = std::nan("");
  EXPECT_THROW(voxel_grid(nan, {}), InputError);
  EXPECT_THROW(lccp_stalk_removal(nan, {}), InputError);
}

}  // namespace
}  // namespace grapebench
