// Registration methods of the multi_view protocol (scene key pipeline.registration):
// how the views of a scan are brought into one frame. Each is a registry entry with
// its own keys (its ICP settings and the method's parameters). Adding one is its
// function here or its own file pair, one registry line and, for a file pair, one
// CMake line.
#pragma once

#include "algorithms/cloud/registration.h"
#include "synth/registry.h"

#include <Eigen/Geometry>

#include <cstdint>
#include <functional>
#include <vector>

namespace grapebench {

// What a method knows besides the views' points.
struct RegistrationContext {
  std::vector<Eigen::Isometry3d> rig_poses;  // each view's camera-to-world pose as the rig has it
  Vec3 axis_point = Vec3::Zero();            // a point on the turntable axis, world frame
  std::uint64_t seed = 0;                    // for a method's own draws (the turntable's angle error)
};

struct RegistrationOutcome {
  // Camera to the merged cloud's frame, per view: the world with true poses, view 0's
  // camera frame for the estimated methods.
  std::vector<Eigen::Isometry3d> poses;
  bool estimated = false;  // false: nothing to score against the truth
};

using RegistrationMethod =
    std::function<RegistrationOutcome(std::vector<RegistrationView>& views, const RegistrationContext& context)>;

const Registry<RegistrationMethod>& registration_registry();

}  // namespace grapebench
