// COLMAP's model as seed 004's pose source: images.txt read into camera-to-world poses,
// malformed lines refused with their number.
#include <gtest/gtest.h>

#include "algorithms/stereo/colmap_sfm.h"

namespace grapebench {
namespace {

TEST(ColmapSfm, ImagesTextGivesCameraToWorldPoses) {
  // A camera turned 90 deg about z (world to camera), at world-to-camera t = (1, 2, 3).
  const double h = std::sqrt(0.5);
  const std::string text = "# Image list\n# comment\n1 " + std::to_string(h) + " 0 0 " + std::to_string(h) +
                           " 1 2 3 1 view_0000.png\n10.5 20.5 7 30 40 -1\n";
  const auto poses = parse_colmap_images(text);
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_EQ(poses[0].first, "view_0000.png");
  const Eigen::Isometry3d& c2w = poses[0].second;
  // The camera centre is -R^T t; R rotates x to y.
  const Eigen::Matrix3d r = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_LT((c2w.translation() - (-r.transpose() * Eigen::Vector3d(1, 2, 3))).norm(), 1e-5);
  EXPECT_LT((c2w.linear() - r.transpose()).norm(), 1e-5);
}

TEST(ColmapSfm, MalformedModelsAreRefused) {
  EXPECT_THROW(parse_colmap_images("1 1 0 0 0 1 2\n"), InputError);                 // too few fields
  EXPECT_THROW(parse_colmap_images("1 2 0 0 0 1 2 3 1 a.png\n\n"), InputError);    // not a unit quaternion
  EXPECT_THROW(parse_colmap_images("1 1 0 0 0 nan 2 3 1 a.png\n\n"), InputError);  // not finite
  try {
    parse_colmap_images("# x\n1 1 0 0 0 1 2 3\n");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(colmap_sfm({}, 1, 1, 0, 0, ColmapParams{}, 1), InputError);
  ColmapParams missing;
  missing.program = "/nonexistent/colmap";
  const RgbImage im{4, 4, std::vector<std::uint8_t>(48, 0)};
  EXPECT_THROW(colmap_sfm({im, im}, 1, 1, 2, 2, missing, 1), InputError);
}

}  // namespace
}  // namespace grapebench
