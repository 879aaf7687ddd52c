// Noise of each model on a plane at 0.5, 1, 2, 3, 4 m against the model's formula.
#include "sensors/d435.h"
#include "sensors/ideal.h"
#include "sensors/kinect_v2.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <cstdio>

namespace grapebench {
namespace {

// A fronto-parallel plane at depth z in front of a camera at the origin looking +y.
struct PlaneSetup {
  RayScene scene;
  Eigen::Isometry3d pose;
  explicit PlaneSetup(double z)
      : scene(Bunch{}, BackgroundPlane{-Vec3::UnitY(), -z, {0.5f, 0.5f, 0.5f}, 0.5}),
        pose(look_at(Vec3::Zero(), Vec3::UnitY())) {}
};

const double kDistances[] = {0.5, 1.0, 2.0, 3.0, 4.0};

TEST(SensorNoise, KinectAxialNoiseMatchesFankhauserFormula) {
  KinectV2Params p;
  p.min_range = 0.3;
  p.edge_filter = false;
  const KinectV2 kinect(p);
  for (double z : kDistances) {
    PlaneSetup s(z);
    const OrganisedCloud c = kinect.capture(s.scene, s.pose, 7);
    // Residuals normalised by the model's sigma at each pixel's incidence angle.
    double sum2 = 0;
    long n = 0;
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (!c.valid[i]) continue;
      const Vec3 dir = c.xyz[i].cast<double>().normalized();
      const double theta = std::acos(std::abs(dir.z()));
      const double r = (c.xyz[i].z() - z) / kinect.axial_sigma(z, theta);
      sum2 += r * r;
      ++n;
    }
    const double ratio = std::sqrt(sum2 / n);
    std::printf("[kinect] z = %.1f m: sigma_z head-on %.2f mm, measured/model %.3f over %ld px\n", z,
                kinect.axial_sigma(z, 0) * 1e3, ratio, n);
    EXPECT_GT(n, 100000);
    EXPECT_NEAR(ratio, 1.0, 0.10) << "z = " << z;
  }
  EXPECT_NEAR(kinect.axial_sigma(1.0, 0) * 1e3, 1.3, 1e-9);  // seed 000: accuracy 2 mm
}

TEST(SensorNoise, D435DepthNoiseMatchesDisparityFormulaAndGrowsAsZSquared) {
  const D435 d435(D435Params{});
  std::vector<double> logz, logrms;
  for (double z : kDistances) {
    PlaneSetup s(z);
    const OrganisedCloud c = d435.capture(s.scene, s.pose, 9);
    double sum2 = 0;
    long n = 0;
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (!c.valid[i]) continue;
      sum2 += std::pow(c.xyz[i].z() - z, 2);
      ++n;
    }
    const double rms = std::sqrt(sum2 / n), model = d435.depth_sigma(z);
    std::printf("[d435] z = %.1f m: rms %.2f mm, model z^2 s/(f B) %.2f mm, ratio %.3f over %ld px\n", z, rms * 1e3,
                model * 1e3, rms / model, n);
    EXPECT_GT(n, 100000);
    EXPECT_NEAR(rms / model, 1.0, 0.10) << "z = " << z;
    logz.push_back(std::log(z));
    logrms.push_back(std::log(rms));
  }
  // Least-squares slope of log rms against log z.
  const double mx = std::accumulate(logz.begin(), logz.end(), 0.0) / logz.size();
  const double my = std::accumulate(logrms.begin(), logrms.end(), 0.0) / logrms.size();
  double sxy = 0, sxx = 0;
  for (std::size_t k = 0; k < logz.size(); ++k) {
    sxy += (logz[k] - mx) * (logrms[k] - my);
    sxx += (logz[k] - mx) * (logz[k] - mx);
  }
  std::printf("[d435] log-log slope of rms error against z: %.3f\n", sxy / sxx);
  EXPECT_NEAR(sxy / sxx, 2.0, 0.1);
}

TEST(SensorNoise, IdealPointsLieOnThePlane) {
  const IdealSensor ideal(IdealParams{});
  for (double z : kDistances) {
    PlaneSetup s(z);
    const OrganisedCloud c = ideal.capture(s.scene, s.pose, 1);
    double worst = 0;
    for (std::size_t i = 0; i < c.size(); ++i) {
      ASSERT_TRUE(c.valid[i]);
      worst = std::max(worst, std::abs(c.xyz[i].z() - z));
    }
    EXPECT_LT(worst, 1e-5) << "z = " << z;
  }
}

TEST(SensorNoise, NoiseScaleZeroIsIdealGeometryAndScalesLinearly) {
  KinectV2Params p;
  p.edge_filter = false;
  p.noise_scale = 0;
  PlaneSetup s(2.0);
  const OrganisedCloud c0 = KinectV2(p).capture(s.scene, s.pose, 3);
  for (std::size_t i = 0; i < c0.size(); ++i) {
    if (c0.valid[i]) {
      ASSERT_NEAR(c0.xyz[i].z(), 2.0, 2e-5);
    }
  }
  D435Params d;
  d.noise_scale = 2;
  const D435 twice(d);
  const OrganisedCloud c2 = twice.capture(s.scene, s.pose, 3);
  double sum2 = 0;
  long n = 0;
  for (std::size_t i = 0; i < c2.size(); ++i) {
    if (c2.valid[i]) {
      sum2 += std::pow(c2.xyz[i].z() - 2.0, 2);
      ++n;
    }
  }
  EXPECT_NEAR(std::sqrt(sum2 / n) / twice.depth_sigma(2.0), 1.0, 0.1);
}

}  // namespace
}  // namespace grapebench
