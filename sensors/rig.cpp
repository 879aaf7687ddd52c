#include "sensors/rig.h"

#include "sensors/camera.h"

#include <cmath>
#include <cstdio>

namespace grapebench {

namespace {

constexpr double kDeg = M_PI / 180;

// A plane facing the camera, `distance` behind the point `through` along the view.
BackgroundPlane plate_behind(const Eigen::Isometry3d& pose, const Vec3& through, const BackgroundSpec& bg) {
  const Vec3 view = pose.linear().col(2);  // camera forward
  BackgroundPlane p;
  p.normal = -view;
  p.offset = p.normal.dot(through + bg.distance * view);
  p.colour = bg.colour;
  p.albedo = bg.albedo;
  return p;
}

std::string numbered(const char* prefix, int k) {
  char b[32];
  std::snprintf(b, sizeof b, "%s_%02d", prefix, k);
  return b;
}

class Turntable : public Rig {
 public:
  explicit Turntable(const TurntableParams& p) : p_(p) {}
  std::string type() const override { return "turntable"; }
  std::vector<RigView> views(const Vec3& centre, double, const BackgroundSpec& bg) const override {
    std::vector<RigView> out;
    const Vec3 axis_point(0, 0, centre.z());  // the turntable axis is the hanging axis
    const double eye_z = p_.camera_height - p_.bunch_top_height;  // relative to the rachis top
    for (int k = 0; k < p_.views; ++k) {
      // Turning the bunch by +a equals moving the camera by -a about the axis.
      const double a = k * p_.step_deg;
      const double phi = -a * kDeg;
      const Vec3 eye(p_.distance * std::cos(phi), p_.distance * std::sin(phi), eye_z);
      RigView v{numbered("view", k), look_at(eye, centre), a, std::nullopt};
      if (bg.type != "none") v.background = plate_behind(v.pose, axis_point, bg);
      out.push_back(v);
    }
    if (p_.bottom_view) {
      const Vec3 eye = centre - Vec3(0, 0, p_.bottom_distance);
      RigView v{"bottom", look_at(eye, centre, Vec3::UnitX()), 0, std::nullopt};
      out.push_back(v);  // the plate is behind the bunch, not above it: no background
    }
    return out;
  }
  nlohmann::ordered_json describe() const override {
    return {{"type", type()}, {"views", p_.views}, {"step_deg", p_.step_deg}, {"distance_m", p_.distance},
            {"camera_height_m", p_.camera_height}, {"bunch_top_height_m", p_.bunch_top_height},
            {"bottom_view", p_.bottom_view}, {"bottom_distance_m", p_.bottom_distance}};
  }

 private:
  TurntableParams p_;
};

class RobotPass : public Rig {
 public:
  explicit RobotPass(const RobotPassParams& p) : p_(p) {}
  std::string type() const override { return "robot_pass"; }
  std::vector<RigView> views(const Vec3& centre, double, const BackgroundSpec& bg) const override {
    // The row runs along x through the bunch; the robot drives along y = -distance.
    std::vector<RigView> out;
    for (int k = 0; k < p_.frames; ++k) {
      // A turned camera (seed 003's left/right views, 45 deg about its y axis) sees the
      // bunch in the pass's middle frame: the pass is shifted by distance tan(yaw).
      const double yaw = p_.yaw_deg * kDeg;
      const double x = centre.x() - p_.distance * std::tan(yaw) + (k - 0.5 * (p_.frames - 1)) * p_.spacing;
      const Vec3 eye(x, centre.y() - p_.distance, centre.z() + p_.height_offset);
      const Vec3 forward(std::sin(yaw), std::cos(yaw), 0);
      RigView v{numbered("frame", k), look_at(eye, eye + forward), 0, std::nullopt};
      if (bg.type != "none") {
        BackgroundPlane p;
        p.normal = -Vec3::UnitY();  // a cloth hung behind the row, fixed in the world
        p.offset = p.normal.dot(Vec3(0, centre.y() + bg.distance, 0));
        p.colour = bg.colour;
        p.albedo = bg.albedo;
        v.background = p;
      }
      out.push_back(v);
    }
    return out;
  }
  nlohmann::ordered_json describe() const override {
    return {{"type", type()}, {"frames", p_.frames}, {"spacing_m", p_.spacing}, {"distance_m", p_.distance},
            {"height_offset_m", p_.height_offset}, {"yaw_deg", p_.yaw_deg}};
  }

 private:
  RobotPassParams p_;
};

class StereoStations : public Rig {
 public:
  explicit StereoStations(const StereoStationsParams& p) : p_(p) {}
  std::string type() const override { return "stereo_stations"; }
  std::vector<RigView> views(const Vec3& centre, double, const BackgroundSpec& bg) const override {
    std::vector<RigView> out;
    for (std::size_t k = 0; k < p_.distances.size(); ++k) {
      const Vec3 eye = centre - Vec3(0, p_.distances[k], 0);
      char name[32];
      std::snprintf(name, sizeof name, "station_%04dmm", static_cast<int>(std::lround(p_.distances[k] * 1000)));
      RigView v{name, look_at(eye, centre), 0, std::nullopt};
      if (bg.type != "none") v.background = plate_behind(v.pose, Vec3(0, 0, centre.z()), bg);
      out.push_back(v);
    }
    return out;
  }
  nlohmann::ordered_json describe() const override {
    return {{"type", type()}, {"distances_m", p_.distances}};
  }

 private:
  StereoStationsParams p_;
};

}  // namespace

std::unique_ptr<Rig> make_turntable(const TurntableParams& p) { return std::make_unique<Turntable>(p); }
std::unique_ptr<Rig> make_robot_pass(const RobotPassParams& p) { return std::make_unique<RobotPass>(p); }
std::unique_ptr<Rig> make_stereo_stations(const StereoStationsParams& p) {
  return std::make_unique<StereoStations>(p);
}

const std::vector<std::string>& rig_types() {
  static const std::vector<std::string> t = {"turntable", "robot_pass", "stereo_stations"};
  return t;
}

std::unique_ptr<Rig> make_rig(const ConfigNode& n) {
  const std::string type = n.get_choice("type", "turntable", rig_types());
  if (type == "turntable") {
    TurntableParams p;
    p.views = static_cast<int>(n.get_int("views", p.views, 1, 360));
    p.step_deg = n.get_real("step_deg", p.step_deg, 0.5, 360);
    p.distance = n.get_real("distance", p.distance, 0.2, 5);
    p.camera_height = n.get_real("camera_height", p.camera_height, 0, 3);
    p.bunch_top_height = n.get_real("bunch_top_height", p.bunch_top_height, 0.1, 3);
    p.bottom_view = n.get_bool("bottom_view", p.bottom_view);
    p.bottom_distance = n.get_real("bottom_distance", p.bottom_distance, 0.2, 5);
    return make_turntable(p);
  }
  if (type == "robot_pass") {
    RobotPassParams p;
    p.frames = static_cast<int>(n.get_int("frames", p.frames, 1, 1000));
    p.spacing = n.get_real("spacing", p.spacing, 0.001, 5);
    p.distance = n.get_real("distance", p.distance, 0.2, 10);
    p.height_offset = n.get_real("height_offset", p.height_offset, -2, 2);
    p.yaw_deg = n.get_real("yaw_deg", p.yaw_deg, -80, 80);
    return make_robot_pass(p);
  }
  StereoStationsParams p;
  if (n.has("distances")) {
    const auto list = n.get_real_list_any("distances", 1, 64, 0.2, 5);
    p.distances = list;
  }
  return make_stereo_stations(p);
}

BackgroundSpec read_background(const ConfigNode& n) {
  BackgroundSpec b;
  b.type = n.get_choice("type", b.type, {"none", "plate", "cloth"});
  b.distance = n.get_real("distance", b.distance, 0.02, 10);
  b.colour = read_rgb(n, "colour", b.colour);
  b.albedo = n.get_real("albedo", b.albedo, 0, 1);
  return b;
}

}  // namespace grapebench
