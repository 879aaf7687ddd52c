// The helpers every sensor model shares (sensors/sensor.h): the pixel mask of what
// Embree holds must be conservative, since the Kinect traces only inside it.
#include "sensors/kinect_v2.h"
#include "sensors/rig.h"
#include "sensors/sensor.h"
#include "synth/foliage.h"
#include "synth/generate.h"
#include "synth/rng.h"

#include <gtest/gtest.h>

namespace grapebench {
namespace {

// Every ray through a point within `margin` - 1 px of an unmasked pixel of the bunch's
// rectangle misses the bunch and the foliage; a fair share of the rectangle is unmasked.
void expect_mask_conservative(const RayScene& scene, const Camera& cam, int margin, std::size_t& unmasked,
                              std::size_t& pixels) {
  const BunchPixels bp = bunch_pixels(scene, cam);
  ASSERT_TRUE(bp.visible);
  const std::vector<std::uint8_t> mask = scene_pixel_mask(scene, cam, bp, margin);
  ASSERT_EQ(mask.size(), static_cast<std::size_t>(bp.u1 - bp.u0) * (bp.v1 - bp.v0));
  const PixelRays ray_at = cam.pixel_rays();
  Rng rng(11);
  std::vector<Ray> rays;
  std::vector<std::pair<int, int>> pixel_of;
  for (int v = bp.v0; v < bp.v1; ++v) {
    for (int u = bp.u0; u < bp.u1; ++u) {
      ++pixels;
      if (mask[static_cast<std::size_t>(v - bp.v0) * (bp.u1 - bp.u0) + u - bp.u0]) continue;
      ++unmasked;
      // The footprint reaches margin - 1 px beyond the pixel on each side.
      for (int k = 0; k < 3; ++k) {
        rays.push_back(ray_at(rng.uniform(u - margin + 1, u + margin), rng.uniform(v - margin + 1, v + margin)));
        pixel_of.emplace_back(u, v);
      }
    }
  }
  std::vector<Hit> hits;
  scene.intersect(rays, hits, true);
  int wrong = 0;
  for (std::size_t i = 0; i < hits.size(); ++i) {
    if (hits[i].valid() && ++wrong <= 5) {
      ADD_FAILURE() << "pixel (" << pixel_of[i].first << ", " << pixel_of[i].second << ") is unmasked but sees "
                    << static_cast<int>(hits[i].part) << " at " << hits[i].t << " m";
    }
  }
  EXPECT_EQ(wrong, 0);
}

TEST(ScenePixelMask, EveryUnmaskedFootprintMissesTheBunchAndTheLeaves) {
  const Bunch bunch = generate_bunch(preset("table-red"), 21);
  FoliageParams fp;
  fp.leaves = 8;
  const RayScene bare(bunch), leafy(bunch, std::nullopt, generate_foliage(fp, bunch, 4));
  const KinectV2 kinect{KinectV2Params{}};
  TurntableParams tp;
  tp.views = 4;
  tp.step_deg = 90;
  tp.bottom_view = true;
  const auto rig = make_turntable(tp);
  for (const RayScene* scene : {&bare, &leafy}) {
    std::size_t unmasked = 0, pixels = 0;
    for (const auto& view : rig->views(scene->bunch_centre(), scene->bunch_radius(), {})) {
      for (const int margin : {1, 4}) {
        expect_mask_conservative(*scene, Camera{kinect.intrinsics(), view.pose}, margin, unmasked, pixels);
      }
    }
    // The mask is worth having: the bare bunch leaves most of its rectangle unmasked.
    if (scene == &bare) {
      EXPECT_GT(unmasked, pixels / 2);
    }
    EXPECT_GT(unmasked, 0u);
  }
}

TEST(ScenePixelMask, StaysConservativeWhereAPixelSpansSeveralStemDiameters) {
  // From 4.5 m a Kinect pixel spans 11 mm, almost two diameters of these 3 mm stems:
  // scene_pixel_mask then bounds them by pixel-long pieces, which must still cover
  // them (pieces 8 px long would leave gaps this finds). A fan of bare stems in every
  // direction, so that none hides behind a berry.
  Bunch fan;
  Rng rng(5);
  for (int i = 0; i < 40; ++i) {
    Stem s;
    s.start = Vec3(0, 0, 1);
    const Vec3 d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    s.end = s.start + 0.12 * d.normalized();
    s.radius = 0.003;
    fan.stems.push_back(s);
  }
  const RayScene scene(fan);
  const KinectV2 kinect{KinectV2Params{}};
  TurntableParams tp;
  tp.views = 3;
  tp.step_deg = 120;
  tp.distance = 4.5;
  tp.camera_height = 1.0;
  tp.bunch_top_height = 1.0;
  const auto rig = make_turntable(tp);
  std::size_t unmasked = 0, pixels = 0;
  for (const auto& view : rig->views(scene.bunch_centre(), scene.bunch_radius(), {})) {
    for (const int margin : {1, 4}) expect_mask_conservative(scene, Camera{kinect.intrinsics(), view.pose}, margin, unmasked, pixels);
  }
  EXPECT_GT(unmasked, pixels / 4);
}

TEST(ScenePixelMask, ACameraInsideTheBunchMasksEverything) {
  const Bunch bunch = generate_bunch(preset("table-red"), 21);
  const RayScene scene(bunch);
  const KinectV2 kinect{KinectV2Params{}};
  const Vec3 eye = bunch.berries[0].centre;  // inside a berry
  const Camera cam{kinect.intrinsics(), look_at(eye, eye + Vec3(0, 1, 0))};
  const BunchPixels bp = bunch_pixels(scene, cam);
  ASSERT_TRUE(bp.visible);
  const std::vector<std::uint8_t> mask = scene_pixel_mask(scene, cam, bp, 4);
  std::size_t set = 0;
  for (auto m : mask) set += m;
  EXPECT_EQ(set, mask.size());
}

}  // namespace
}  // namespace grapebench
