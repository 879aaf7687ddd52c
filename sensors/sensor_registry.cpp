#include "sensors/sensor_registry.h"

#include "sensors/d435.h"
#include "sensors/ideal.h"
#include "sensors/kinect_v2.h"
#include "sensors/stereo_rgb.h"

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


}  // namespace grapebench
