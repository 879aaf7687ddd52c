// The OSMesa images agree with the exact ray-cast geometry of both cameras.
#include "sensors/ideal.h"
#include "sensors/stereo_rgb.h"
#include "synth/generate.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace grapebench {
namespace {

TEST(StereoRgb, RenderedSilhouettesMatchTheExactLabelsOfBothCameras) {
  const Bunch b = generate_bunch(preset("summer-black"), 4);
  const RayScene scene(b);
  StereoRgbParams p;
  p.background = StereoRgbParams::Background::Plain;
  p.plain_colour = {0, 1, 0};  // pure green: no berry or stem is this colour
  p.noise_scale = 0;
  p.width = 400;
  p.height = 300;
  p.pixel_pitch_um = 12;  // same field of view as 800 x 600 at 6 um
  const StereoRgb rig(p);
  const Vec3 c = scene.bounds_centre();
  const auto pose = look_at(c - Vec3(0, 0.6, 0), c);
  const OrganisedCloud frame = rig.capture(scene, pose, 1);
  ASSERT_EQ(frame.left_image.size(), static_cast<std::size_t>(400 * 300 * 3));
  Eigen::Isometry3d right_pose = pose;
  right_pose.translation() = pose * Vec3(p.baseline, 0, 0);
  const OrganisedCloud exact_right = capture_exact(scene, Camera{rig.intrinsics(), right_pose});
  auto iou = [&](const std::vector<std::uint8_t>& image, const OrganisedCloud& exact) {
    std::size_t both = 0, either = 0;
    for (std::size_t i = 0; i < exact.size(); ++i) {
      const bool rendered = !(image[3 * i] < 10 && image[3 * i + 1] > 245 && image[3 * i + 2] < 10);
      const bool truth = exact.valid[i] != 0;
      both += rendered && truth;
      either += rendered || truth;
    }
    return static_cast<double>(both) / either;
  };
  const double left = iou(frame.left_image, frame), right = iou(frame.right_image, exact_right);
  std::printf("[stereo] silhouette IoU rendered vs exact: left %.4f, right %.4f\n", left, right);
  EXPECT_GT(left, 0.97);
  EXPECT_GT(right, 0.97);
  // And the two views differ by the disparity: the right image is not the left one.
  EXPECT_NE(frame.left_image, frame.right_image);
}

TEST(StereoRgb, SameSeedSameImages) {
  const Bunch b = generate_bunch(preset("wine-red"), 2);
  const RayScene scene(b);
  StereoRgbParams p;
  p.width = 320;
  p.height = 240;
  const StereoRgb rig(p);
  const Vec3 c = scene.bounds_centre();
  const auto pose = look_at(c - Vec3(0, 0.5, 0), c);
  const OrganisedCloud a = rig.capture(scene, pose, 8), b2 = rig.capture(scene, pose, 8);
  EXPECT_EQ(a.left_image, b2.left_image);
  EXPECT_EQ(a.right_image, b2.right_image);
}

}  // namespace
}  // namespace grapebench
