#include "sensors/sensor.h"

#include "sensors/d435.h"
#include "sensors/ideal.h"
#include "sensors/kinect_v2.h"
#include "sensors/stereo_rgb.h"

#include <tbb/parallel_for.h>

#include <cmath>

namespace grapebench {

const std::vector<SensorEntry>& sensor_registry() {
  static const std::vector<SensorEntry> entries = {
      {"kinect_v2", "Kinect v2 time of flight, 512 x 424 (seeds 000, 002)", KinectV2::create},
      {"d435", "RealSense D435 active stereo, 848 x 480 (seed 003)", D435::create},
      {"stereo_rgb", "binocular colour stereo, 800 x 600, OSMesa images (seed 001)", StereoRgb::create},
      {"ideal", "noise-free pinhole rays, the control", IdealSensor::create},
  };
  return entries;
}

std::unique_ptr<Sensor> make_sensor(const ConfigNode& node) {
  std::vector<std::string> names;
  for (const auto& e : sensor_registry()) names.push_back(e.type);
  const std::string type = node.get_choice("type", "kinect_v2", names);
  for (const auto& e : sensor_registry()) {
    if (e.type == type) return e.create(node);
  }
  node.fail("type", "unknown sensor");
}

BunchPixels bunch_pixels(const RayScene& scene, const Camera& cam) {
  BunchPixels b;
  b.visible = scene.has_bunch() && cam.ball_pixels(scene.bounds_centre(), scene.bounds_radius(), b.u0, b.v0, b.u1, b.v1);
  return b;
}

OrganisedCloud frame_for(const RayScene& scene, const Camera& cam, const BunchPixels& bp) {
  OrganisedCloud out;
  const int H = cam.K.height;
  if (scene.background()) {
    out.resize(cam.K.width, H);
  } else {
    out.resize(cam.K.width, H, bp.v0, bp.visible ? bp.v1 : bp.v0);
  }
  return out;
}

std::size_t trace_row(const RayScene& scene, const Camera& cam, int v, int ua, int ub, int bu0, int bu1,
                      bool sees_bunch, std::vector<double>& uv, std::vector<Hit>& hits) {
  hits.resize(cam.K.width);
  const PixelRays ray_at = cam.pixel_rays();
  for (int u = ua; u < ub; ++u) {
    if (!(sees_bunch && u >= bu0 && u < bu1)) hits[u] = scene.background_hit(ray_at(u + 0.5, v + 0.5));
  }
  if (!sees_bunch) return 0;
  uv.resize(2 * static_cast<std::size_t>(bu1 - bu0));
  for (int u = bu0; u < bu1; ++u) {
    uv[2 * (u - bu0)] = u + 0.5;
    uv[2 * (u - bu0) + 1] = v + 0.5;
  }
  scene.intersect_image_points(ray_at, uv.data(), bu1 - bu0, hits.data() + bu0);
  return static_cast<std::size_t>(bu1 - bu0);
}

void for_rows(int height, const std::function<void(int, int)>& body) {
  const int block = 8;
  tbb::parallel_for(0, (height + block - 1) / block, [&](int b) {
    body(b * block, std::min(height, (b + 1) * block));
  });
}

}  // namespace grapebench
