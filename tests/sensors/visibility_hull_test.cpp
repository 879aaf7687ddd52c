// The visibility hull on shapes whose hidden space is known in closed form, its
// determinism across thread counts, and its errors.
#include "sensors/visibility_hull.h"

#include "synth/config.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

namespace grapebench {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kR = 0.02;  // m, the berry's radius

Bunch one_berry() {
  Bunch b;
  Berry berry;
  berry.radius = kR;
  b.berries.push_back(berry);
  return b;
}

// A narrow camera at `distance` along `axis`, looking at the origin.
Camera camera_on(const Vec3& axis, double distance) {
  const Vec3 up = std::abs(axis.z()) > 0.9 ? Vec3::UnitX() : Vec3::UnitZ();
  return Camera{intrinsics_from_hfov(64, 64, 2 * std::atan(0.1 / distance) * 180 / kPi), look_at(distance * axis, Vec3::Zero(), up)};
}

TEST(VisibilityHull, SixViewsOfABallSeeEverythingButTheBall) {
  const RayScene scene(one_berry());
  std::vector<Camera> cams;
  for (const Vec3& a : std::vector<Vec3>{Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)}) {
    cams.push_back(camera_on(a, 1.0));
  }
  const VisibilityHull h = visibility_hull(scene, cams, {0.0005, 0.005});
  const double ball = 4.0 / 3 * kPi * kR * kR * kR;
  EXPECT_NEAR(h.volume / ball, 1, 0.005) << h.hidden << " of " << h.samples;
  EXPECT_GT(h.segments, h.samples);  // every sample was traced at least once
}

// One far camera above the ball: hidden are the ball and its shadow down to the box
// floor, in the box [-r, r]^3 (no margin): the lower half ball is inside the shadow,
// so the hidden volume is the upper half ball plus a cylinder r long,
// 2/3 pi r^3 + pi r^3 (orthographic limit; at 10 m the cone widens by 0.2 %).
TEST(VisibilityHull, OneViewHidesTheShadowBehindTheBall) {
  const RayScene scene(one_berry());
  const VisibilityHull h = visibility_hull(scene, {camera_on(Vec3::UnitZ(), 10.0)}, {0.0005, 0.0});
  const double expected = (2.0 / 3 + 1) * kPi * kR * kR * kR;
  EXPECT_NEAR(h.volume / expected, 1, 0.01) << h.hidden << " of " << h.samples;
  EXPECT_NEAR(h.box_volume, 8 * kR * kR * kR, 1e-9);
}

TEST(VisibilityHull, SameCountAtAnyThreadCount) {
  const RayScene scene(one_berry());
  const std::vector<Camera> cams{camera_on(Vec3::UnitX(), 0.5), camera_on(Vec3(0.6, 0.8, 0), 0.5)};
  VisibilityHull one, two;
  {
    const tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = visibility_hull(scene, cams, {0.001, 0.01});
  }
  {
    const tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = visibility_hull(scene, cams, {0.001, 0.01});
  }
  EXPECT_EQ(one.hidden, two.hidden);
  EXPECT_EQ(one.segments, two.segments);
}

TEST(VisibilityHull, BadInputIsAnErrorNamingIt) {
  const RayScene scene(one_berry());
  const std::vector<Camera> cams{camera_on(Vec3::UnitX(), 1.0)};
  const auto message = [&](const std::vector<Camera>& c, const VisibilityHullParams& p) {
    try {
      visibility_hull(scene, c, p);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(cams, {0.0, 0.003}).find("voxel"), std::string::npos);
  EXPECT_NE(message(cams, {std::nan(""), 0.003}).find("voxel"), std::string::npos);
  EXPECT_NE(message(cams, {0.001, -1}).find("margin"), std::string::npos);
  EXPECT_NE(message(cams, {1e-4, 0.5}).find("raise voxel"), std::string::npos);
  EXPECT_NE(message({}, {}).find("no cameras"), std::string::npos);
  const RayScene wall_only(Bunch{}, BackgroundPlane{});  // nothing to bound the box
  EXPECT_NE([&] {
    try {
      visibility_hull(wall_only, cams);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  }().find("no berries or stems"), std::string::npos);
}

}  // namespace
}  // namespace grapebench
