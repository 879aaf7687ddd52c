// Seed 003's size estimators on shapes with known answers.
#include "algorithms/size/cylinder_fit.h"
#include "algorithms/size/ellipsoid_fit.h"
#include "algorithms/size/percentile_box.h"
#include "synth/rng.h"

#include <gtest/gtest.h>

#include <cmath>

namespace grapebench {
namespace {

TEST(PercentileBox, ExactOnAUniformBox) {
  // A regular grid filling a 0.3 x 0.2 x 0.1 m box: percentiles of a uniform grid
  // are exact linear interpolants.
  std::vector<Vec3> pts;
  const int n = 41;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) pts.emplace_back(0.3 * i / (n - 1), 0.2 * j / (n - 1) - 0.5, 0.1 * k / (n - 1) + 1);
  const PointCloud c = to_point_cloud(pts);
  const PercentileBox full = percentile_box(c, {0});
  EXPECT_NEAR(full.edges[0], 0.3, 1e-12);
  EXPECT_NEAR(full.edges[1], 0.2, 1e-12);
  EXPECT_NEAR(full.edges[2], 0.1, 1e-12);
  EXPECT_NEAR(full.diagonals[0], std::hypot(0.3, 0.2), 1e-12);
  EXPECT_NEAR(full.volume(), 0.006, 1e-14);
  const PercentileBox p20 = percentile_box(c, {0.2});  // the paper's 20th / 80th
  EXPECT_NEAR(p20.edges[0], 0.6 * 0.3, 1e-12);
  EXPECT_NEAR(p20.minimum.x(), 0.2 * 0.3, 1e-12);
  EXPECT_THROW(percentile_box(c, {0.5}), InputError);
}

TEST(EllipsoidFit, RecoversAKnownEllipsoidFromAFullSampling) {
  const Vec3 semi(0.07, 0.045, 0.03);
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.6, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 centre(0.1, -0.2, 1.4);
  Rng rng(4);
  std::vector<Vec3> pts;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 u = Vec3(rng.normal(), rng.normal(), rng.normal()).normalized();
    pts.push_back(centre + rot * u.cwiseProduct(semi));
  }
  const EllipsoidFit f = ellipsoid_fit(to_point_cloud(pts));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(f.radii(i) / semi(i), 1, 0.01) << i;
  EXPECT_LT((f.centre - centre).norm(), 1e-6);
  EXPECT_LT(1 - std::abs(f.axes.col(0).dot(rot.col(0))), 1e-6);
}

TEST(EllipsoidFit, DegenerateInputIsAnError) {
  std::vector<Vec3> flat;
  for (int i = 0; i < 100; ++i) flat.emplace_back(std::cos(i), std::sin(i), 0);
  EXPECT_THROW(ellipsoid_fit(to_point_cloud(flat)), InputError);
  EXPECT_THROW(ellipsoid_fit(PointCloud(5, 3)), InputError);
}

TEST(CylinderFit, RecoversAKnownCylinder) {
  // Lateral surface of a cylinder, radius 6 cm, height 20 cm, axis tilted, with 1 mm noise.
  const Vec3 axis = Vec3(0.2, 0.1, 1).normalized(), base(0.05, 0.02, 1.2);
  Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  Rng rng(6);
  std::vector<Vec3> pts;
  for (int i = 0; i < 4000; ++i) {
    const double t = 2 * M_PI * rng.uniform(), h = 0.2 * rng.uniform();
    pts.push_back(base + h * axis + 0.06 * (std::cos(t) * e1 + std::sin(t) * e2) + 0.001 * Vec3(rng.normal(), rng.normal(), rng.normal()));
  }
  const CylinderFit f = cylinder_fit(to_point_cloud(pts));
  EXPECT_NEAR(f.radius, 0.06, 0.002);
  EXPECT_NEAR(f.height, 0.2, 0.005);
  EXPECT_GT(std::abs(f.axis.dot(axis)), 0.999);
  EXPECT_GT(f.inliers, 3000);  // the normal term (weight 0.1) rejects points with noisy normals
  // Deterministic: the same fit twice.
  EXPECT_EQ(cylinder_fit(to_point_cloud(pts)).radius, f.radius);
}

}  // namespace
}  // namespace grapebench
