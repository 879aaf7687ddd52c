#include "algorithms/stereo/rectified_triangulation.h"

#include <gtest/gtest.h>

#include "synth/config.h"

namespace grapebench {
namespace {

// Project a point into both rectified cameras, then triangulate its exact disparity.
TEST(RectifiedTriangulation, ExactForAnExactDisparity) {
  StereoPair cam;
  cam.fx = 1000, cam.fy = 1010, cam.cx = 399.5, cam.cy = 301.25, cam.baseline = 0.05;
  for (const Vec3& P : {Vec3(0.03, -0.02, 0.7), Vec3(-0.21, 0.15, 1.1), Vec3(0, 0, 0.35)}) {
    const double xl = cam.fx * P.x() / P.z() + cam.cx, y = cam.fy * P.y() / P.z() + cam.cy;
    const double xr = cam.fx * (P.x() - cam.baseline) / P.z() + cam.cx;
    const Vec3 Q = triangulate_rectified(cam, xl, y, xl - xr);
    EXPECT_NEAR((Q - P).norm(), 0, 1e-12) << P.transpose();
  }
}

// Eq. 8 as printed omits the principal point: off by (c_x, c_y) Z / f.
TEST(RectifiedTriangulation, UsesThePrincipalPoint) {
  StereoPair cam;
  cam.fx = cam.fy = 1000, cam.cx = 400, cam.cy = 300, cam.baseline = 0.05;
  const Vec3 Q = triangulate_rectified(cam, 400, 300, 50);
  EXPECT_NEAR(Q.x(), 0, 1e-15);
  EXPECT_NEAR(Q.y(), 0, 1e-15);
  EXPECT_NEAR(Q.z(), 1.0, 1e-15);
}

TEST(RectifiedTriangulation, ANonPositiveDisparityIsAnError) {
  StereoPair cam;
  cam.fx = cam.fy = 1000, cam.baseline = 0.05;
  EXPECT_THROW(triangulate_rectified(cam, 1, 1, 0), InputError);
  EXPECT_THROW(triangulate_rectified(cam, 1, 1, -3), InputError);
  EXPECT_THROW(triangulate_rectified(cam, 1, 1, std::nan("")), InputError);
}

}  // namespace
}  // namespace grapebench
