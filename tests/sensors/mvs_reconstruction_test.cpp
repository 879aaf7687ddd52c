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

}  // namespace
}  // namespace grapebench
