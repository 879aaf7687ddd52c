// Point clouds as estimators take them: N x 3, metres, one point per row.
#pragma once

#include "synth/config.h"
#include "synth/types.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>

#include <string>
#include <vector>

namespace grapebench {

// An 8-bit colour (sensor RGB).
using Rgb8 = std::array<std::uint8_t, 3>;

using PointCloud = Eigen::Matrix<double, Eigen::Dynamic, 3>;

PointCloud to_point_cloud(const std::vector<Vec3>& points);

// Throws InputError naming `who` when the cloud is unusable: fewer than `min_points`
// rows, or a non-finite coordinate (with its row).
void require_points(const PointCloud& cloud, Eigen::Index min_points, const std::string& who);
// For volume estimators: at least 4 finite points that do not all lie in one plane
// (smallest principal extent above 1e-9 of the largest).
void require_solid(const PointCloud& cloud, const std::string& who);

}  // namespace grapebench
