// The OSMesa images agree with the exact ray-cast geometry of both cameras.
#include "sensors/stereo_rgb.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <tuple>

#include "sensors/ideal.h"
#include "sensors/sensor_registry.h"
#include "synth/foliage.h"
#include "synth/generate.h"

namespace grapebench {
namespace {

// Intersection over union of the pixels an image draws anything on (not the pure
// green backdrop) and the pixels with an exact return.
double silhouette_iou(const std::vector<std::uint8_t>& image, const OrganisedCloud& exact) {
  std::size_t both = 0, either = 0;
  for (std::size_t i = 0; i < exact.size(); ++i) {
    const bool rendered = !(image[3 * i] < 10 && image[3 * i + 1] > 245 && image[3 * i + 2] < 10);
    const bool truth = exact.valid[i] != 0;
    both += rendered && truth;
    either += rendered || truth;
  }
  return static_cast<double>(both) / static_cast<double>(either);
}

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
  const double left = silhouette_iou(frame.left_image, frame), right = silhouette_iou(frame.right_image, exact_right);
  std::printf("[stereo] silhouette IoU rendered vs exact: left %.4f, right %.4f\n", left, right);
  EXPECT_GT(left, 0.97);
  EXPECT_GT(right, 0.97);
  // And the two views differ by the disparity: the right image is not the left one.
  EXPECT_NE(frame.left_image, frame.right_image);
}

// With the vine row's foliage in the ray scene, the images draw it too (leaves,
// shoots, the cordon): rendered silhouettes of everything match the exact returns.
TEST(StereoRgb, TheFoliageIsDrawnWhereTheRaySceneSeesIt) {
  const Bunch b = generate_bunch(preset("summer-black"), 4);
  const RayScene scene(b, std::nullopt, generate_foliage(FoliageParams{}, b, 9));
  StereoRgbParams p;
  p.background = StereoRgbParams::Background::Plain;
  p.plain_colour = {0, 1, 0};
  p.noise_scale = 0;
  p.width = 400;
  p.height = 300;
  p.pixel_pitch_um = 12;
  const StereoRgb rig(p);
  const Vec3 c = scene.bounds_centre();
  const OrganisedCloud frame = rig.capture(scene, look_at(c - Vec3(0, 0.9, 0), c), 1);
  std::size_t foliage = 0;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    foliage += frame.label[i] == static_cast<std::uint8_t>(Part::Leaf) ||
               frame.label[i] == static_cast<std::uint8_t>(Part::Cane);
  }
  const double iou = silhouette_iou(frame.left_image, frame);
  std::printf("[stereo] with foliage (%zu leaf/cane pixels): silhouette IoU %.4f\n", foliage, iou);
  EXPECT_GT(foliage, frame.size() / 10);
  EXPECT_GT(iou, 0.97);
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

// Seed 001's three lights: under the overshadow the cluster's front is in its own
// shadow (darker than under front light) while the backlit leaves behind are brighter;
// overcast light is flat (less contrast on the cluster than sunny front light); a sun
// that a berry blocks leaves the berries behind it in cast shadow.
TEST(StereoRgb, LightPresetsAndCastShadows) {
  const Bunch b = generate_bunch(preset("table-red"), 6);
  const RayScene scene(b);
  StereoRgbParams p;
  p.width = 320;
  p.height = 240;
  p.pixel_pitch_um = 15;
  p.noise_scale = 0;
  const Vec3 c = scene.bounds_centre();
  const auto pose = look_at(c - Vec3(0, 0.6, 0), c);
  // Mean grey level of the bunch's pixels and of the backdrop's.
  auto means = [&](StereoRgbParams::Light light) {
    p.light = light;
    const OrganisedCloud f = StereoRgb(p).capture(scene, pose, 3);
    double bunch = 0, bunch2 = 0, back = 0;
    int nb = 0, nk = 0;
    for (std::size_t i = 0; i < f.size(); ++i) {
      const double g = (f.left_image[3 * i] + f.left_image[3 * i + 1] + f.left_image[3 * i + 2]) / 3.0;
      if (f.valid[i])
        bunch += g, bunch2 += g * g, ++nb;
      else
        back += g, ++nk;
    }
    const double mean = bunch / nb;
    return std::tuple{mean, back / nk, std::sqrt(bunch2 / nb - mean * mean)};
  };
  using L = StereoRgbParams::Light;
  const auto [front_bunch, front_back, front_sd] = means(L::Front);
  const auto [over_bunch, over_back, over_sd] = means(L::Overshadow);
  const auto [cast_bunch, cast_back, cast_sd] = means(L::Overcast);
  std::printf(
      "[stereo] mean grey bunch/backdrop (bunch sd): front %.1f/%.1f (%.1f), overshadow %.1f/%.1f (%.1f), "
      "overcast %.1f/%.1f (%.1f)\n",
      front_bunch, front_back, front_sd, over_bunch, over_back, over_sd, cast_bunch, cast_back, cast_sd);
  EXPECT_GT(front_bunch, 1.3 * over_bunch);
  EXPECT_GT(over_back, front_back);
  EXPECT_GT(front_sd, 1.3 * cast_sd);
  // Cast shadows: the same sun with and without the scene blocking it. With the sun
  // grazing from the side most berries shade their neighbours.
  p.light = L::Custom;
  p.sun_elevation_deg = 10, p.sun_azimuth_deg = 80, p.sun = 1.0, p.ambient = 0.1;
  const OrganisedCloud f = StereoRgb(p).capture(scene, pose, 3);
  std::vector<Vec3> from, to;
  const Vec3 back = Vec3(0, -1, 0);  // the camera looks along +y: behind it is -y
  const double az = 80 * M_PI / 180, el = 10 * M_PI / 180;
  const Vec3 sun = std::cos(el) * (Eigen::AngleAxisd(az, Vec3::UnitZ()) * back) + std::sin(el) * Vec3::UnitZ();
  std::vector<std::size_t> pix;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!f.valid[i]) continue;
    const Vec3 n = pose.linear() * f.normal[i].cast<double>();
    if (n.dot(sun) < 0.5) continue;  // well lit when not blocked
    const Vec3 w = pose * f.xyz[i].cast<double>();
    from.push_back(w + 1e-4 * n), to.push_back(w + 20 * sun), pix.push_back(i);
  }
  std::vector<char> blocked;
  scene.occluded(from, to, blocked);
  double shadowed = 0, lit = 0;
  int ns = 0, nl = 0;
  for (std::size_t j = 0; j < pix.size(); ++j) {
    const double g = f.left_image[3 * pix[j]];  // red: the berries' own channel
    if (blocked[j])
      shadowed += g, ++ns;
    else
      lit += g, ++nl;
  }
  ASSERT_GT(ns, 50);
  ASSERT_GT(nl, 50);
  std::printf("[stereo] facing the sun: lit %.1f (%d px), in cast shadow %.1f (%d px)\n", lit / nl, nl, shadowed / ns,
              ns);
  EXPECT_GT(lit / nl, 2 * shadowed / ns);
}

}  // namespace
}  // namespace grapebench

namespace grapebench {
namespace {

std::string error_of(const std::string& yaml) {
  try {
    nlohmann::ordered_json params;
    sensor_registry().create(ConfigNode::load_string(yaml, "scene.yaml"), params);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The photoreal path's keys are read by their own tables, with file:line and range,
// and only where they apply.
TEST(StereoRgb, TheRayRenderersKeysAreCheckedWithTheirRanges) {
  EXPECT_NE(error_of("type: stereo_rgb\nrenderer: ray\n").find("light"), std::string::npos);
  const std::string bloom = error_of("type: stereo_rgb\nrenderer: ray\nlight: front\nappearance:\n  bloom: 2\n");
  EXPECT_NE(bloom.find("scene.yaml:5"), std::string::npos) << bloom;
  EXPECT_NE(bloom.find("bloom"), std::string::npos) << bloom;
  EXPECT_NE(bloom.find("[0, 1]"), std::string::npos) << bloom;
  const std::string lens = error_of("type: stereo_rgb\nrenderer: ray\nlight: front\ncamera: {f_number: 0.5}\n");
  EXPECT_NE(lens.find("f_number"), std::string::npos) << lens;
  const std::string sky = error_of("type: stereo_rgb\nrenderer: ray\nlight: overcast\ncamera: {sky_samples: 0}\n");
  EXPECT_NE(sky.find("sky_samples"), std::string::npos) << sky;
  EXPECT_NE(sky.find("[1, 64]"), std::string::npos) << sky;
  const std::string stride = error_of("type: stereo_rgb\nrenderer: ray\nlight: overcast\ncamera: {sky_stride: 3}\n");
  EXPECT_NE(stride.find("sky_stride"), std::string::npos) << stride;
  EXPECT_NE(stride.find("[1, 2]"), std::string::npos) << stride;
  const std::string opengl = error_of("type: stereo_rgb\nappearance: {bloom: 0.5}\n");
  EXPECT_NE(opengl.find("renderer: ray or cycles"), std::string::npos) << opengl;
  const std::string cycles = error_of("type: stereo_rgb\nrenderer: ray\nlight: front\ncycles: {samples: 4}\n");
  EXPECT_NE(cycles.find("renderer: cycles"), std::string::npos) << cycles;
  EXPECT_EQ(error_of("type: stereo_rgb\nrenderer: ray\nlight: overcast\ncamera: {jpeg_quality: 90, samples: 1}\n"), "");
}

// Seed 001's lights captured together (a sweep over the `ray` renderer's light renders
// each pair once): each pair the same to the bit as its sensor's own capture, the
// labels too. Only sensors that differ in their light alone share a together_key.
TEST(StereoRgb, TheRayRenderersPairsUnderSeveralLightsAreEachLightsOwn) {
  const Bunch b = generate_bunch(preset("table-red"), 4);
  const RayScene scene(b, std::nullopt, generate_foliage(FoliageParams{}, b, 9));
  StereoRgbParams p;
  p.renderer = StereoRgbParams::Renderer::Ray;
  p.width = 160;
  p.height = 120;
  p.pixel_pitch_um = 30;
  p.camera.samples = 2;
  p.camera.jpeg_quality = 90;  // the camera's JPEG file too
  std::vector<StereoRgb> rigs;
  for (const auto l : {StereoRgbParams::Light::Front, StereoRgbParams::Light::Overshadow, StereoRgbParams::Light::Overcast}) {
    p.light = l;
    rigs.emplace_back(p);
  }
  p.light = StereoRgbParams::Light::Custom;
  p.sun_azimuth_deg = 90, p.sun_size_deg = 2;
  rigs.emplace_back(p);
  std::vector<const Sensor*> sensors;
  for (const StereoRgb& r : rigs) {
    EXPECT_EQ(r.together_key(), rigs.front().together_key());
    sensors.push_back(&r);
  }
  const Vec3 c = scene.bunch_centre();
  const auto pose = look_at(c - Vec3(0, 0.6, 0), c);
  const std::vector<OrganisedCloud> together = rigs.front().capture_together(sensors, scene, pose, 3);
  ASSERT_EQ(together.size(), rigs.size());
  for (std::size_t k = 0; k < rigs.size(); ++k) {
    const OrganisedCloud alone = rigs[k].capture(scene, pose, 3);
    EXPECT_EQ(together[k].left_image, alone.left_image) << "light " << k;
    EXPECT_EQ(together[k].right_image, alone.right_image) << "light " << k;
    EXPECT_FALSE(alone.left_jpeg.empty());
    EXPECT_EQ(together[k].left_jpeg, alone.left_jpeg) << "light " << k;
    std::size_t other = 0;  // labels, validity, and colours where valid (the cloud's only defined ones)
    for (std::size_t i = 0; i < alone.size(); ++i)
      other += together[k].valid[i] != alone.valid[i] || together[k].label[i] != alone.label[i] ||
               (alone.valid[i] && together[k].rgb[i] != alone.rgb[i]);
    EXPECT_EQ(other, 0u) << "light " << k;
  }
  EXPECT_NE(together[0].left_image, together[2].left_image);
  // Anything but the light keeps sensors apart; OpenGL's are captured alone.
  StereoRgbParams q = p;
  q.camera.auto_target = 0.3;
  EXPECT_NE(StereoRgb(q).together_key(), rigs.front().together_key());
  q = p;
  q.baseline = 0.06;
  EXPECT_NE(StereoRgb(q).together_key(), rigs.front().together_key());
  q = p;
  q.renderer = StereoRgbParams::Renderer::OpenGl;
  EXPECT_EQ(StereoRgb(q).together_key(), "");
  q.renderer = StereoRgbParams::Renderer::Cycles;
  EXPECT_EQ(StereoRgb(q).together_key(), "");
}

// The whole pair through the ray renderer and the camera chain: the same bytes at 1
// and 2 threads; the left image's colours are the cloud's.
TEST(StereoRgb, TheRayRenderedPairIsTheSameAtAnyThreadCount) {
  const Bunch b = generate_bunch(preset("table-red"), 4);
  const RayScene scene(b, std::nullopt, generate_foliage(FoliageParams{}, b, 9));
  StereoRgbParams p;
  p.renderer = StereoRgbParams::Renderer::Ray;
  p.light = StereoRgbParams::Light::Front;
  p.width = 160;
  p.height = 120;
  p.pixel_pitch_um = 30;
  p.camera.samples = 2;
  const StereoRgb rig(p);
  const Vec3 c = scene.bunch_centre();
  const auto pose = look_at(c - Vec3(0, 0.6, 0), c);
  OrganisedCloud one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = rig.capture(scene, pose, 3);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = rig.capture(scene, pose, 3);
  }
  EXPECT_EQ(one.left_image, two.left_image);
  EXPECT_EQ(one.right_image, two.right_image);
  EXPECT_NE(one.left_image, one.right_image);
  std::size_t berries = 0;
  for (std::size_t i = 0; i < one.size(); ++i) {
    if (!one.valid[i]) continue;
    berries += one.label[i] == static_cast<std::uint8_t>(Part::Berry);
    EXPECT_EQ(one.rgb[i][0], one.left_image[3 * i]);
  }
  EXPECT_GT(berries, 100u);

  // Another noise_seed redraws the images' noise and nothing else: the same geometry
  // and labels, other pixels, the same mean (the scene the images show is unchanged).
  StereoRgbParams q = p;
  q.noise_seed = 1;
  const OrganisedCloud other = StereoRgb(q).capture(scene, pose, 3);
  ASSERT_EQ(other.size(), one.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    ASSERT_EQ(other.label[i], one.label[i]) << "pixel " << i;
    ASSERT_EQ(other.valid[i], one.valid[i]) << "pixel " << i;
  }
  EXPECT_NE(other.left_image, one.left_image);
  EXPECT_NE(other.right_image, one.right_image);
  double mean_diff = 0, mean_abs = 0;
  for (std::size_t i = 0; i < one.left_image.size(); ++i) {
    const double d = double(other.left_image[i]) - double(one.left_image[i]);
    mean_diff += d;
    mean_abs += std::abs(d);
  }
  mean_diff /= double(one.left_image.size());
  mean_abs /= double(one.left_image.size());
  EXPECT_LT(std::abs(mean_diff), 0.1 * mean_abs) << mean_diff << " DN against " << mean_abs;
  EXPECT_GT(mean_abs, 0.5);
}

}  // namespace
}  // namespace grapebench
