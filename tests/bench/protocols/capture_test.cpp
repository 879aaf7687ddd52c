#include "bench/protocols/capture.h"

#include <gtest/gtest.h>

#include "bench/scene_file.h"
#include "synth/generate.h"
#include "synth/rng.h"

namespace grapebench {
namespace {

// Seed 001's photoreal scene renders each pair once for its three lights
// (Sensor::capture_together); each light's pair must be the one it gets alone. Its
// reproducer: bunch 1 at the 450 mm station, front light, came out otherwise in the
// full scene while every light's shadow rays were cast in one Embree batch (its
// packets then held other rays, and a ray grazing an edge was decided otherwise); the
// unit test's small image (tests/sensors/render) did not show it.
TEST(Capture, SeedOnesThreeLightsTogetherGiveEachLightsPairToTheBit) {
  const SceneSet set = load_scene_set(GRAPEBENCH_SOURCE_DIR "/scenes/seed001_black_ray.yaml");
  ASSERT_EQ(set.conditions.size(), 3u);
  const Scene& scene = set.conditions.front().scene;
  const BunchJob job = bunch_jobs(scene).at(1);
  const Bunch bunch = generate_bunch(job.params, job.seed);
  const RayScene rays = scene_rays(scene, bunch, job.seed);
  const std::size_t k = 5;  // the 450 mm station
  const RigView view = scene.rig->views(rays.bunch_centre(), rays.bunch_radius(), scene.background).at(k);
  ASSERT_EQ(view.name, "station_0450mm");
  std::vector<const Sensor*> sensors;
  for (const Condition& c : set.conditions) sensors.push_back(c.scene.sensor.get());
  const RayScene seen = rays.with_background(view.background);
  const std::uint64_t seed = derive_seed(scan_seed(job), k);
  const std::vector<OrganisedCloud> together = sensors.front()->capture_together(sensors, seen, view.pose, seed);
  ASSERT_EQ(together.size(), 3u);
  for (std::size_t l = 0; l < sensors.size(); ++l) {
    const OrganisedCloud alone = sensors[l]->capture(seen, view.pose, seed);
    ASSERT_FALSE(alone.left_image.empty());
    EXPECT_TRUE(together[l].left_image == alone.left_image) << set.conditions[l].label;
    EXPECT_TRUE(together[l].right_image == alone.right_image) << set.conditions[l].label;
  }
}

}  // namespace
}  // namespace grapebench
