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
      if (bg.type != BackgroundType::None) v.background = plate_behind(v.pose, axis_point, bg);
      out.push_back(v);
    }
    if (p_.bottom_view) {
      const Vec3 eye = centre - Vec3(0, 0, p_.bottom_distance);
      RigView v{"bottom", look_at(eye, centre, Vec3::UnitX()), 0, std::nullopt};
      out.push_back(v);  // the plate is behind the bunch, not above it: no background
    }
    return out;
  }
  nlohmann::ordered_json describe() const override { return with_type(type(), turntable_param_table().to_json(p_)); }

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
      if (bg.type != BackgroundType::None) {
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
  nlohmann::ordered_json describe() const override { return with_type(type(), robot_pass_param_table().to_json(p_)); }

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
      if (bg.type != BackgroundType::None) v.background = plate_behind(v.pose, Vec3(0, 0, centre.z()), bg);
      out.push_back(v);
    }
    return out;
  }
  nlohmann::ordered_json describe() const override {
    return with_type(type(), stereo_stations_param_table().to_json(p_));
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

const ParamTable<TurntableParams>& turntable_param_table() {
  using P = TurntableParams;
  static const ParamTable<P> table = ParamTable<P>()
      .integer("views", "count", &P::views, 1, 360, "views around the bunch (seed 000: 12; seed 002: 8)")
      .real("step_deg", "deg", &P::step_deg, 0.5, 360, "turntable step between views (seed 000: 30; seed 002: 45)")
      .real("distance", "m", &P::distance, 0.2, 5, "horizontal distance of the camera from the bunch axis (seed 000: 1 m)")
      .real("camera_height", "m", &P::camera_height, 0, 3, "camera height above the floor")
      .real("bunch_top_height", "m", &P::bunch_top_height, 0.1, 3, "height above the floor where the rachis top hangs")
      .boolean("bottom_view", &P::bottom_view, "add a view from below, looking up (seed 002 Sect. 2.2)")
      .real("bottom_distance", "m", &P::bottom_distance, 0.2, 5, "bottom view: distance below the bunch centre")
      .when("bottom_view: true", [](const P& p) { return p.bottom_view; });
  return table;
}

const ParamTable<RobotPassParams>& robot_pass_param_table() {
  using P = RobotPassParams;
  static const ParamTable<P> table = ParamTable<P>()
      .integer("frames", "count", &P::frames, 1, 1000, "frames along the pass (seed 003: single RealSense frames)")
      .real("spacing", "m", &P::spacing, 0.001, 5, "robot travel between frames")
      .real("distance", "m", &P::distance, 0.2, 10, "camera distance from the row plane (seed 003: 1.5 m)")
      .real("height_offset", "m", &P::height_offset, -2, 2, "camera height relative to the bunch centre")
      .real("yaw_deg", "deg", &P::yaw_deg, -80, 80, "camera turn about the vertical (seed 003: front 0, sides +-45)");
  return table;
}

const ParamTable<StereoStationsParams>& stereo_stations_param_table() {
  using P = StereoStationsParams;
  static const ParamTable<P> table = ParamTable<P>().reals(
      "distances", "m", &P::distances, 1, 64, 0.2, 5, "stereo rig stations in front of the bunch (seed 001: 350-1100 mm)");
  return table;
}

const ParamTable<BackgroundSpec>& background_param_table() {
  using P = BackgroundSpec;
  static const ParamTable<P> table =
      ParamTable<P>()
          .choice("type", &P::type,
                  {{"none", BackgroundType::None}, {"plate", BackgroundType::Plate}, {"cloth", BackgroundType::Cloth}},
                  "none; plate: behind the bunch as seen from each view (seed 000); cloth: fixed behind the row (seed 003)")
          .real("distance", "m", &P::distance, 0.02, 10, "behind the bunch axis")
          .rgb("colour", &P::colour, "colour in the RGB frame")
          .real("albedo", "-", &P::albedo, 0, 1, "infrared reflectivity relative to a berry's 0.6");
  return table;
}

const Registry<std::unique_ptr<Rig>>& rig_registry() {
  static const Registry<std::unique_ptr<Rig>> registry(
      "rig", {entry<std::unique_ptr<Rig>>("turntable", "turntable views at one distance, optional bottom view (seeds 000, 002)",
                                          turntable_param_table(), TurntableParams{},
                                          [](const TurntableParams& p, const ConfigNode&) { return make_turntable(p); }),
              entry<std::unique_ptr<Rig>>("robot_pass", "frames of a camera moving along a row (seed 003)",
                                          robot_pass_param_table(), RobotPassParams{},
                                          [](const RobotPassParams& p, const ConfigNode&) { return make_robot_pass(p); }),
              entry<std::unique_ptr<Rig>>("stereo_stations", "the stereo rig at each distance in front of the bunch (seed 001)",
                                          stereo_stations_param_table(), StereoStationsParams{},
                                          [](const StereoStationsParams& p, const ConfigNode&) {
                                            return make_stereo_stations(p);
                                          })});
  return registry;
}

std::unique_ptr<Rig> make_rig(const ConfigNode& n) {
  nlohmann::ordered_json ignored;
  return rig_registry().create(n, ignored, "turntable");
}

BackgroundSpec read_background(const ConfigNode& n) {
  BackgroundSpec b;
  background_param_table().read(n, b);
  return b;
}

}  // namespace grapebench
