// Capture rigs: where the camera stands for each view, and the background it sees.
// World frame as in synth/: z up, the bunch hanging from its rachis top at the origin.
#pragma once

#include "sensors/ray_scene.h"
#include "synth/config.h"
#include "synth/registry.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace grapebench {

// Background behind the bunch: none, a plate that stays behind the bunch as seen
// from each view (turntable rigs: the plate of seed 000), or a cloth fixed in the
// world behind the row (robot pass, seed 003's black cloth).
enum class BackgroundType { None, Plate, Cloth };
struct BackgroundSpec {
  BackgroundType type = BackgroundType::None;
  double distance = 0.25;     // m behind the bunch axis, [0.02, 10]
  Rgb colour{0.35f, 0.35f, 0.35f};
  double albedo = 0.5;  // infrared reflectivity relative to a berry's 0.6, [0, 1]
};
const ParamTable<BackgroundSpec>& background_param_table();  // scene section `background:`
BackgroundSpec read_background(const ConfigNode& node);

struct RigView {
  std::string name;                 // "view_00", "bottom", ...
  Eigen::Isometry3d pose;           // camera to world
  double turntable_angle_deg = 0;   // rotation of the bunch this view stands for
  std::optional<BackgroundPlane> background;
};

class Rig {
 public:
  virtual ~Rig() = default;
  virtual std::string type() const = 0;
  // Views for a bunch whose bounding sphere is (centre, radius).
  virtual std::vector<RigView> views(const Vec3& centre, double radius, const BackgroundSpec& bg) const = 0;
  virtual nlohmann::ordered_json describe() const = 0;
};

// Seed 000: 12 views every 30 deg at 1 m, camera 0.75 m high; seed 002: 8 x 45 deg
// plus a bottom view (camera below, looking up).
struct TurntableParams {
  int views = 12;                   // [1, 360]
  double step_deg = 30;             // deg, [0.5, 360]
  double distance = 1.0;            // m, horizontal from the bunch axis, [0.2, 5]
  double camera_height = 0.75;      // m above the floor, [0, 3]
  double bunch_top_height = 0.95;   // m above the floor where the rachis top hangs, [0.1, 3]
  bool bottom_view = false;         // seed 002
  double bottom_distance = 0.6;     // m below the bunch centre, [0.2, 5]
};

// Seed 003: camera moving parallel to a row at 1.5 m, a frame every `spacing` m,
// turned by `yaw_deg` about the vertical (front 0, left/right +-45).
struct RobotPassParams {
  int frames = 5;              // [1, 1000]
  double spacing = 0.1;        // m, [0.001, 5]
  double distance = 1.5;       // m from the row plane, [0.2, 10]
  double height_offset = 0.0;  // m, camera height relative to the bunch centre, [-2, 2]
  double yaw_deg = 0;          // deg, [-80, 80]
};

// Seed 001: the stereo rig in front of the bunch at each distance (350-1100 mm).
struct StereoStationsParams {
  std::vector<double> distances{0.35, 0.5, 0.65, 0.8, 0.95, 1.1};  // m, each in [0.2, 5]
};

const ParamTable<TurntableParams>& turntable_param_table();
const ParamTable<RobotPassParams>& robot_pass_param_table();
const ParamTable<StereoStationsParams>& stereo_stations_param_table();
// Every rig type; adding one is its file pair plus one line in rig_registry().
const Registry<std::unique_ptr<Rig>>& rig_registry();
std::unique_ptr<Rig> make_rig(const ConfigNode& node);
std::unique_ptr<Rig> make_turntable(const TurntableParams& p);
std::unique_ptr<Rig> make_robot_pass(const RobotPassParams& p);
std::unique_ptr<Rig> make_stereo_stations(const StereoStationsParams& p);

}  // namespace grapebench
