#include "sensors/sensor.h"

#include "sensors/d435.h"
#include "sensors/ideal.h"
#include "sensors/kinect_v2.h"
#include "sensors/stereo_rgb.h"

#include <tbb/parallel_for.h>

#include <cmath>

namespace grapebench {

namespace {

// A registry line for sensor class S built from its parameter struct P.
template <class S, class P>
RegistryEntry<std::unique_ptr<Sensor>> sensor(std::string type, std::string summary, const ParamTable<P>& table) {
  return entry<std::unique_ptr<Sensor>>(std::move(type), std::move(summary), table, P{},
                                        [](const P& p, const ConfigNode&) { return std::make_unique<S>(p); });
}

}  // namespace

const Registry<std::unique_ptr<Sensor>>& sensor_registry() {
  static const Registry<std::unique_ptr<Sensor>> registry(
      "sensor", {
                    sensor<KinectV2>("kinect_v2", "Kinect v2 time of flight, 512 x 424 (seeds 000, 002)", kinect_v2_param_table()),
                    sensor<D435>("d435", "RealSense D435 active stereo, 848 x 480 (seed 003)", d435_param_table()),
                    sensor<StereoRgb>("stereo_rgb", "binocular colour stereo, 800 x 600, OSMesa images (seed 001)",
                                      stereo_rgb_param_table()),
                    sensor<IdealSensor>("ideal", "noise-free pinhole rays, the control", ideal_param_table()),
                });
  return registry;
}

std::unique_ptr<Sensor> make_sensor(const ConfigNode& node) {
  nlohmann::ordered_json ignored;
  return sensor_registry().create(node, ignored, "kinect_v2");
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
