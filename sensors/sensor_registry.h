// The sensor registry: scene files name a sensor model by `type`. Adding one is its
// file pair, one line in sensor_registry.cpp and one CMake line.
#pragma once

#include "sensors/sensor.h"
#include "synth/registry.h"

#include <memory>

namespace grapebench {

const Registry<std::unique_ptr<Sensor>>& sensor_registry();
// Builds the sensor a scene's `sensor:` mapping names (default kinect_v2); errors name file:line.
std::unique_ptr<Sensor> make_sensor(const ConfigNode& node);

}  // namespace grapebench
