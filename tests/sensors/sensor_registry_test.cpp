// Every registered sensor, built from scene text through the registry, on a ball of
// radius 5 cm at 1 m: its returns lie on the ball within the model's noise, and cover
// the ball's projected disc.
#include "sensors/sensor_registry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace grapebench {
namespace {

struct Expectation {
  double median_abs_mm;  // largest median |distance to the ball centre - R|
  double coverage_lo;    // berry returns / the disc's pixel area, at least
};

// Per model: Kinect v2 1.3 mm axial sd at 1 m plus mixed pixels on the rim; D435
// sigma_z = z^2 s / (f B) = 3.6 mm at 1 m; the stereo rig and the ideal model carry the
// exact ray-cast depth.
Expectation expectation(const std::string& type) {
  if (type == "kinect_v2") return {3.0, 0.7};
  if (type == "d435") return {5.0, 0.7};
  return {0.05, 0.95};
}

TEST(SensorRegistry, EverySensorSeesABallAtOneMetreWhereItIs) {
  const double R = 0.05;
  Bunch ball;
  ball.berries.push_back({Vec3::Zero(), R, {0.5f, 0.1f, 0.2f}, -1});
  const RayScene scene(ball);
  const Eigen::Isometry3d pose = look_at(Vec3(0, -1, 0), Vec3::Zero());
  int sensors = 0;
  for (const auto& type : sensor_registry().types()) {
    nlohmann::ordered_json params;
    const auto sensor = sensor_registry().create(ConfigNode::load_string("type: " + type, "scene.yaml"), params);
    EXPECT_EQ(params["type"].get<std::string>(), type);
    const OrganisedCloud c = sensor->capture(scene, pose, 7);
    std::vector<double> dev;
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (!c.valid[i]) continue;
      EXPECT_EQ(c.label[i], static_cast<std::uint8_t>(Part::Berry)) << type;
      const Vec3 world = pose * c.xyz[i].cast<double>();
      dev.push_back(std::abs(world.norm() - R));
    }
    ASSERT_GT(dev.size(), 100u) << type;
    std::nth_element(dev.begin(), dev.begin() + static_cast<long>(dev.size() / 2), dev.end());
    const double median_mm = dev[dev.size() / 2] * 1e3;
    // The disc the ball covers: angular radius asin(R / d), in pixels of focal fx.
    const Intrinsics k = sensor->intrinsics();
    const double disc = M_PI * std::pow(k.fx * std::tan(std::asin(R / 1.0)), 2) * k.fy / k.fx;
    const double coverage = static_cast<double>(dev.size()) / disc;
    std::printf("[sensor] %-10s %6zu returns, coverage %.3f of the disc, median |r - R| %.3f mm\n", type.c_str(),
                dev.size(), coverage, median_mm);
    const Expectation e = expectation(type);
    EXPECT_LT(median_mm, e.median_abs_mm) << type;
    EXPECT_GT(coverage, e.coverage_lo) << type;
    EXPECT_LT(coverage, 1.05) << type;
    ++sensors;
  }
  EXPECT_EQ(sensors, static_cast<int>(sensor_registry().entries().size()));
  EXPECT_GE(sensors, 4);
}

}  // namespace
}  // namespace grapebench
