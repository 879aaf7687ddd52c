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

std::array<std::uint8_t, 3> shade(const Rgb& c, const Vec3& normal, const Vec3& ray_dir) {
  // Light at the camera: ambient plus Lambert.
  const double k = 0.35 + 0.65 * std::max(0.0, -normal.dot(ray_dir));
  auto byte = [&](float x) { return static_cast<std::uint8_t>(std::lround(std::clamp(x * k, 0.0, 1.0) * 255)); };
  return {byte(c.r), byte(c.g), byte(c.b)};
}

BunchPixels bunch_pixels(const RayScene& scene, const Camera& cam) {
  BunchPixels b;
  b.visible = scene.has_bunch() && cam.ball_pixels(scene.bounds_centre(), scene.bounds_radius(), b.u0, b.v0, b.u1, b.v1);
  return b;
}

std::size_t trace_row(const RayScene& scene, const Camera& cam, int v, int ua, int ub, int bu0, int bu1,
                      bool sees_bunch, std::vector<Ray>& rays, std::vector<Hit>& hits) {
  rays.resize(cam.K.width);
  hits.resize(cam.K.width);
  for (int u = ua; u < ub; ++u) rays[u] = cam.ray(u + 0.5, v + 0.5);
  for (int u = ua; u < ub; ++u) {
    if (!(sees_bunch && u >= bu0 && u < bu1)) hits[u] = scene.background_hit(rays[u]);
  }
  if (!sees_bunch) return 0;
  scene.intersect(rays.data() + bu0, bu1 - bu0, hits.data() + bu0);
  return static_cast<std::size_t>(bu1 - bu0);
}

void for_rows(int height, const std::function<void(int, int)>& body) {
  const int block = 8;
  tbb::parallel_for(0, (height + block - 1) / block, [&](int b) {
    body(b * block, std::min(height, (b + 1) * block));
  });
}

void OrganisedCloud::resize(int w, int h) {
  width = w;
  height = h;
  const std::size_t n = size();
  valid.assign(n, 0);
  label.assign(n, static_cast<std::uint8_t>(Part::None));
  berry.resize(n);
  xyz.resize(n);
  normal.resize(n);
  rgb.resize(n);
  true_depth.resize(n);
}

std::size_t OrganisedCloud::valid_count() const {
  std::size_t n = 0;
  for (auto v : valid) n += v;
  return n;
}

std::vector<Vec3> OrganisedCloud::bunch_points() const {
  std::vector<Vec3> pts;
  for (std::size_t i = 0; i < size(); ++i) {
    if (valid[i] && label[i] <= static_cast<std::uint8_t>(Part::Peduncle)) pts.push_back(xyz[i].cast<double>());
  }
  return pts;
}

}  // namespace grapebench
