// Seed 004's fast-path reconstruction (sensors/mvs_reconstruction.h): fused points keep
// their exact labels and lie on the surfaces without noise; the depth error follows the
// stereo formula z^2 sigma_d / (f b); the same seed gives the same cloud.
#include <gtest/gtest.h>

#include <cmath>

#include "sensors/ideal.h"
#include "sensors/mvs_reconstruction.h"
#include "sensors/ray_scene.h"
#include "sensors/rig.h"
#include "synth/foliage.h"
#include "synth/generate.h"
#include "synth/rng.h"
#include "synth/vine_row.h"

namespace grapebench {
namespace {

struct Row {
  Bunch bunch;
  RayScene rays;
};

Row small_row() {
  VineRowParams p;
  p.vines = 1, p.bunches_per_vine = 2;
  std::vector<Bunch> bunches{generate_bunch(preset("green-table"), 1), generate_bunch(preset("green-table"), 2)};
  Bunch row = vine_row(bunches, p, 5);
  FoliageParams f;
  f.leaves = 60, f.row_half_length = 0.4, f.occlusion = 0;
  Foliage leaves = generate_foliage(f, row, 6);
  RayScene rays(row, std::nullopt, leaves);
  return {std::move(row), std::move(rays)};
}

Scan pass(const RayScene& rays, int frames, double spacing) {
  IdealParams ip;
  ip.width = 320, ip.height = 240, ip.hfov_deg = 60;
  RobotPassParams rp;
  rp.frames = frames, rp.spacing = spacing, rp.distance = 0.8;
  return scan_bunch(rays, IdealSensor(ip), *make_robot_pass(rp), BackgroundSpec{}, 3);
}

TEST(MvsReconstruction, FusedPointsCarryTheirTrueLabels) {
  const Row row = small_row();
  const Scan scan = pass(row.rays, 3, 0.15);
  MvsNoiseParams p;
  p.disparity_sd = 0;
  FusionParams fusion;
  fusion.voxel = 0.001, fusion.min_views = 1;
  const FusedCloud c = mvs_reconstruction(scan, p, fusion, 1);
  std::size_t berries = 0, on_surface = 0, leaves = 0, canes = 0;
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    leaves += c.labels[i] == Part::Leaf;
    canes += c.labels[i] == Part::Cane;
    if (c.labels[i] != Part::Berry) continue;
    ++berries;
    double d = 1e9;
    for (const Berry& b : row.bunch.berries) d = std::min(d, std::abs((c.points[i] - b.centre).norm() - b.radius));
    on_surface += d < 0.001 * std::sqrt(3.0);  // the centroid stays in its voxel
  }
  EXPECT_GT(berries, 1000u);
  EXPECT_GT(leaves, 1000u);
  EXPECT_GT(canes, 50u);
  EXPECT_GE(static_cast<double>(on_surface), 0.995 * static_cast<double>(berries));
  EXPECT_LE(c.points.size(), c.returns);
}

TEST(MvsReconstruction, DepthErrorFollowsTheStereoFormulaAndTheSeed) {
  const Row row = small_row();
  const Scan scan = pass(row.rays, 2, 0.1);
  MvsNoiseParams p;
  p.disparity_sd = 0.7;
  FusionParams fusion;
  fusion.voxel = 0.002, fusion.min_views = 1;
  const FusedCloud c = mvs_reconstruction(scan, p, fusion, 1);
  // Both cameras look along +y from the same plane: z is the distance along y.
  const double f = scan.views[0].camera.K.fx, y0 = scan.views[0].camera.centre().y();
  const double b = (scan.views[1].camera.centre() - scan.views[0].camera.centre()).norm();
  ASSERT_NEAR(b, 0.1, 1e-9);
  // The fused point's own depth carries the error (about 2 % here), so the ratio is
  // checked on average: E[(z + e)^2] / z^2 = 1 + (sd / z)^2.
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < c.points.size(); i += 7, ++n) {
    const double z = c.points[i].y() - y0;
    sum += c.depth_sd[i] / (z * z * 0.7 / (f * b));
  }
  EXPECT_NEAR(sum / n, 1, 0.01);
  const FusedCloud again = mvs_reconstruction(scan, p, fusion, 1), other = mvs_reconstruction(scan, p, fusion, 2);
  ASSERT_EQ(again.points.size(), c.points.size());
  for (std::size_t i = 0; i < c.points.size(); ++i) ASSERT_EQ(again.points[i], c.points[i]);
  std::size_t same = 0;
  for (std::size_t i = 0; i < std::min(c.points.size(), other.points.size()); ++i) same += other.points[i] == c.points[i];
  EXPECT_LT(same, c.points.size() / 100);  // another seed, other errors
  Scan one = scan;
  one.views.resize(1);
  EXPECT_THROW(mvs_reconstruction(one, p, fusion, 1), InputError);
}

// The correlated error field: unit variance, and neighbours k px apart along a row or a
// column correlated by exp(-k / L); L = 0 is the independent draws, bit for bit.
TEST(MvsReconstruction, CorrelatedFieldHasUnitVarianceAndExponentialCorrelation) {
  // About w h / (4 L^2) independent values: 19,000 at L = 2.5, so the sample variance
  // has an sd near 0.01; the tolerances below are 5 sd.
  const int w = 800, h = 600;
  const std::vector<double> iid = correlated_normal_field(w, h, 0, 17);
  for (std::size_t i = 0; i < iid.size(); i += 97) ASSERT_EQ(iid[i], hashed_normal(17, i));
  for (const double L : {1.0, 2.5}) {
    const std::vector<double> e = correlated_normal_field(w, h, L, 17);
    double s = 0, ss = 0;
    for (const double x : e) s += x, ss += x * x;
    const double n = static_cast<double>(e.size()), var = ss / n - (s / n) * (s / n);
    EXPECT_NEAR(s / n, 0, 0.05) << L;
    EXPECT_NEAR(var, 1, 0.06) << L;
    // The first row and column too: the recursion starts stationary.
    double edge = 0;
    for (int x = 0; x < w; ++x) edge += e[static_cast<std::size_t>(x)] * e[static_cast<std::size_t>(x)];
    for (int y = 0; y < h; ++y) edge += e[static_cast<std::size_t>(y * w)] * e[static_cast<std::size_t>(y * w)];
    EXPECT_NEAR(edge / (w + h), 1, 0.35) << L;
    for (const int k : {1, 2, 4}) {
      double row = 0, col = 0;
      int nr = 0, nc = 0;
      for (int y = 0; y + k < h; ++y) {
        for (int x = 0; x + k < w; ++x) {
          const std::size_t i = static_cast<std::size_t>(y * w + x);
          row += e[i] * e[i + static_cast<std::size_t>(k)], ++nr;
          col += e[i] * e[i + static_cast<std::size_t>(k * w)], ++nc;
        }
      }
      const double expected = std::exp(-k / L);
      EXPECT_NEAR(row / nr / var, expected, 0.05) << "L " << L << " lag " << k;
      EXPECT_NEAR(col / nc / var, expected, 0.05) << "L " << L << " lag " << k;
    }
  }
  EXPECT_NE(correlated_normal_field(w, h, 1.0, 18), correlated_normal_field(w, h, 1.0, 17));
}

// Two views 10 m apart (their points never share a voxel) of a step: berries at 1 m in
// columns 0-9, a leaf at 2 m in columns 10-29 (20 rows). Exact returns on each pixel's
// ray.
Scan step_scan() {
  Scan scan;
  for (int k = 0; k < 2; ++k) {
    ScanView v;
    v.rig.name = "view_" + std::to_string(k);
    v.camera.K = Intrinsics{30, 20, 100, 100, 15, 10};
    v.camera.pose = Eigen::Isometry3d::Identity();
    v.camera.pose.translation() = Vec3(10.0 * k, 0, 0);
    v.rig.pose = v.camera.pose;
    v.cloud.resize(30, 20);
    for (int r = 0; r < 20; ++r) {
      for (int u = 0; u < 30; ++u) {
        const std::size_t i = static_cast<std::size_t>(r * 30 + u);
        const double z = u < 10 ? 1.0 : 2.0;
        v.cloud.valid[i] = 1;
        v.cloud.label[i] = static_cast<std::uint8_t>(u < 10 ? Part::Berry : Part::Leaf);
        v.cloud.true_depth[i] = static_cast<float>(z);
        v.cloud.xyz[i] = Eigen::Vector3f(static_cast<float>((u + 0.5 - 15) / 100 * z),
                                         static_cast<float>((r + 0.5 - 10) / 100 * z), static_cast<float>(z));
        v.cloud.rgb[i] = {0, 0, 0};
      }
    }
    scan.views.push_back(std::move(v));
  }
  return scan;
}

// Foreground fattening: leaf pixels within r px of the berries' edge take the berries'
// depth (all of them at fraction 1, about half at 0.5) and keep their label; off, the
// leaf stays at 2 m.
TEST(MvsReconstruction, EdgeFatteningMovesPixelsBehindAnEdgeToTheForeground) {
  const Scan scan = step_scan();
  FusionParams fusion;
  fusion.voxel = 0.0005, fusion.min_views = 1;
  const auto leaves_at_1m = [&](const MvsNoiseParams& p) {
    const FusedCloud c = mvs_reconstruction(scan, p, fusion, 3);
    int n = 0;
    for (std::size_t i = 0; i < c.points.size(); ++i) n += c.labels[i] == Part::Leaf && std::abs(c.points[i].z() - 1) < 1e-6;
    return n;
  };
  MvsNoiseParams p;
  p.disparity_sd = 0;
  EXPECT_EQ(leaves_at_1m(p), 0);
  p.edge_fattening_px = 2;
  EXPECT_EQ(leaves_at_1m(p), 2 * 20 * 2);  // columns 10 and 11, 20 rows, 2 views
  p.edge_fattening_px = 3;
  EXPECT_EQ(leaves_at_1m(p), 3 * 20 * 2);
  p.edge_fattening_fraction = 0.5;
  EXPECT_NEAR(leaves_at_1m(p), 60, 20);
  const std::vector<float> nearest = nearest_depth_within(scan.views[0].cloud, 2);
  EXPECT_EQ(nearest[11], 1.0f);
  EXPECT_EQ(nearest[12], 2.0f);
  EXPECT_EQ(nearest[0], 1.0f);
  EXPECT_TRUE(nearest_depth_within(scan.views[0].cloud, 0).empty());
}

// Window smoothing: each return takes the mean disparity of the surfaces within r px.
// On the step (berries at 1 m in columns 0-9, a leaf at 2 m beyond), r = 2: column 9
// sees 3 berry and 2 leaf columns, mean inverse depth (3 + 2 / 2) / 5 = 0.8 m^-1, so
// 1.25 m; column 10, (2 + 3 / 2) / 5 = 0.7 m^-1; column 12 only leaf. Labels stay.
TEST(MvsReconstruction, WindowSmoothingAveragesTheDisparitiesOfTheBlock) {
  const Scan scan = step_scan();
  const std::vector<float> m = window_mean_depth(scan.views[0].cloud, 2);
  for (const int row : {0, 10, 19}) {
    EXPECT_FLOAT_EQ(m[static_cast<std::size_t>(row * 30 + 7)], 1.0f);
    EXPECT_FLOAT_EQ(m[static_cast<std::size_t>(row * 30 + 9)], 1.25f);
    EXPECT_FLOAT_EQ(m[static_cast<std::size_t>(row * 30 + 10)], static_cast<float>(1 / 0.7));
    EXPECT_FLOAT_EQ(m[static_cast<std::size_t>(row * 30 + 12)], 2.0f);
  }
  EXPECT_TRUE(window_mean_depth(scan.views[0].cloud, 0).empty());
  // Through the reconstruction: column 9's berries at 1.25 m, column 10's leaf at 1.43 m.
  FusionParams fusion;
  fusion.voxel = 0.0005, fusion.min_views = 1;
  MvsNoiseParams p;
  p.disparity_sd = 0, p.window_px = 2;
  const FusedCloud c = mvs_reconstruction(scan, p, fusion, 3);
  int berries_at = 0, leaves_at = 0;
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    berries_at += c.labels[i] == Part::Berry && std::abs(c.points[i].z() - 1.25) < 1e-5;
    leaves_at += c.labels[i] == Part::Leaf && std::abs(c.points[i].z() - 1 / 0.7) < 1e-5;
  }
  EXPECT_EQ(berries_at, 20 * 2);  // 20 rows, 2 views
  EXPECT_EQ(leaves_at, 20 * 2);
}

// Pixel locking: on a slanted surface (depth 1 m to 1.3 m across 60 columns, views
// 10 m apart, so the `baseline` key of 5 cm sets b) each return's disparity is off by
// exactly -A sin(2 pi delta), delta the true disparity's fractional part.
TEST(MvsReconstruction, PixelLockingDrawsDisparitiesTowardWholePixels) {
  const int w = 60, h = 4;
  const double f = 1000;
  Scan scan;
  for (int k = 0; k < 2; ++k) {
    ScanView v;
    v.rig.name = "view_" + std::to_string(k);
    v.camera.K = Intrinsics{w, h, f, f, w / 2.0, h / 2.0};
    v.camera.pose = Eigen::Isometry3d::Identity();
    v.camera.pose.translation() = Vec3(10.0 * k, 0, 0);
    v.rig.pose = v.camera.pose;
    v.cloud.resize(w, h);
    for (int r = 0; r < h; ++r) {
      for (int u = 0; u < w; ++u) {
        const std::size_t i = static_cast<std::size_t>(r * w + u);
        const double z = 1 + 0.005 * u;
        v.cloud.valid[i] = 1;
        v.cloud.label[i] = static_cast<std::uint8_t>(Part::Leaf);
        v.cloud.true_depth[i] = static_cast<float>(z);
        v.cloud.xyz[i] = Eigen::Vector3f(static_cast<float>((u + 0.5 - w / 2.0) / f * z),
                                         static_cast<float>((r + 0.5 - h / 2.0) / f * z), static_cast<float>(z));
        v.cloud.rgb[i] = {0, 0, 0};
      }
    }
    scan.views.push_back(std::move(v));
  }
  FusionParams fusion;
  fusion.voxel = 0.0005, fusion.min_views = 1;
  MvsNoiseParams p;
  p.disparity_sd = 0, p.baseline = 0.05, p.pixel_locking_px = 0.2;
  const double fb = f * p.baseline;
  const FusedCloud c = mvs_reconstruction(scan, p, fusion, 3);
  ASSERT_EQ(c.points.size(), static_cast<std::size_t>(2 * w * h));
  double worst = 0, largest = 0;
  for (const Vec3& x : c.points) {
    const Vec3 local = x - Vec3(x.x() > 5 ? 10.0 : 0.0, 0, 0);  // the view's own frame
    const int u = static_cast<int>(std::lround(local.x() / local.z() * f + w / 2.0 - 0.5));
    ASSERT_GE(u, 0);
    ASSERT_LT(u, w);
    const double d = fb / (1 + 0.005 * u), e = fb / local.z() - d;
    const double expected = -p.pixel_locking_px * std::sin(2 * M_PI * (d - std::floor(d)));
    worst = std::max(worst, std::abs(e - expected));
    largest = std::max(largest, std::abs(e));
  }
  EXPECT_LT(worst, 0.002);  // px: the depth step is linearised
  EXPECT_GT(largest, 0.19);
  p.pixel_locking_px = 0;  // off: exact
  for (const Vec3& x : mvs_reconstruction(scan, p, fusion, 3).points) {
    const Vec3 local = x - Vec3(x.x() > 5 ? 10.0 : 0.0, 0, 0);
    const int u = static_cast<int>(std::lround(local.x() / local.z() * f + w / 2.0 - 0.5));
    EXPECT_NEAR(local.z(), 1 + 0.005 * u, 1e-6);
  }
}

}  // namespace
}  // namespace grapebench
